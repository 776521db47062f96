// Vite build of the studio page. File names are fixed (no content hashes):
// the C++ build embeds every file of dist/ into the strata binary
// (index.html, assets/app.js, assets/app.css, and assets/app-views.js: the
// canvas and text pane, imported by app.js once the file list is shown).
import { defineConfig } from 'vite';

export default defineConfig({
  base: './',
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
