// Vite build of the studio page. File names are fixed (no content hashes):
// the C++ build embeds every file of dist/ into the strata binary
// (index.html, assets/app.js, assets/app-views.js: the canvas and text
// pane, imported by app.js once the file list is shown, and
// assets/app-uPlot.esm.js, the chart's library). The stylesheet is put in
// index.html itself (inlineCss): the page's first paint, and the file list
// in it, wait for no request of their own (a parser-inserted script, as
// index.html's list drawing is, also waits for every stylesheet before it).
import { defineConfig } from 'vite';

function inlineCss() {
  return {
    name: 'strata-inline-css',
    apply: 'build',
    transformIndexHtml: {
      order: 'post',
      handler(html, ctx) {
        if (!ctx.bundle) return html;
        for (const [name, asset] of Object.entries(ctx.bundle)) {
          if (!name.endsWith('.css') || asset.type !== 'asset') continue;
          const link = new RegExp(`<link rel="stylesheet"[^>]*href="[^"]*${name.replace(/[.*+?^${}()|[\]\\]/g, '\\$&')}"[^>]*>`);
          if (!link.test(html)) continue;
          const css = String(asset.source).replace(/<\/style/gi, '<\\/style');
          html = html.replace(link, () => `<style>${css}</style>`);
          delete ctx.bundle[name];
        }
        return html;
      },
    },
  };
}

export default defineConfig({
  base: './',
  plugins: [inlineCss()],
  build: {
    outDir: 'dist',
    emptyOutDir: true,
    assetsDir: 'assets',
    assetsInlineLimit: 100000,
    cssCodeSplit: false,
    modulePreload: false,
    sourcemap: false,
    chunkSizeWarningLimit: 2000,
    rollupOptions: {
      output: {
        entryFileNames: 'assets/app.js',
        chunkFileNames: 'assets/app-[name].js',
        assetFileNames: (info) => {
          const n = (info.names && info.names[0]) || info.name || '';
          return n.endsWith('.css') ? 'assets/app.css' : 'assets/[name][extname]';
        },
      },
    },
  },
  server: {
    proxy: { '/api': process.env.STRATA_URL || 'http://127.0.0.1:7070' },
  },
});
