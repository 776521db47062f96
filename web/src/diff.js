// A line diff (longest common subsequence) of two texts, for a save's
// conflict: rows {op: ' ' | '-' | '+', text}, '-' only in a, '+' only in b.
// Common first and last lines are matched first; a middle larger than
// kMaxCells cells is shown as all removed then all added.
export const kMaxCells = 4e6;

export function lineDiff(a, b) {
  const A = a.split('\n'), B = b.split('\n');
  let pre = 0;
  while (pre < A.length && pre < B.length && A[pre] === B[pre]) pre++;
  let suf = 0;
  while (suf < A.length - pre && suf < B.length - pre && A[A.length - 1 - suf] === B[B.length - 1 - suf]) suf++;
  const a2 = A.slice(pre, A.length - suf), b2 = B.slice(pre, B.length - suf);
  const rows = A.slice(0, pre).map((text) => ({ op: ' ', text }));
  const n = a2.length, m = b2.length;
  if (n * m > kMaxCells) {
    for (const text of a2) rows.push({ op: '-', text });
    for (const text of b2) rows.push({ op: '+', text });
  } else {
    // L[i][j]: the LCS length of a2[i..] and b2[j..], in one flat array.
    const L = new Uint32Array((n + 1) * (m + 1));
    for (let i = n - 1; i >= 0; i--) {
      for (let j = m - 1; j >= 0; j--) {
        L[i * (m + 1) + j] = a2[i] === b2[j] ? L[(i + 1) * (m + 1) + j + 1] + 1 : Math.max(L[(i + 1) * (m + 1) + j], L[i * (m + 1) + j + 1]);
      }
    }
    let i = 0, j = 0;
    while (i < n || j < m) {
      if (i < n && j < m && a2[i] === b2[j]) { rows.push({ op: ' ', text: a2[i] }); i++; j++; }
      else if (j < m && (i >= n || L[i * (m + 1) + j + 1] > L[(i + 1) * (m + 1) + j])) { rows.push({ op: '+', text: b2[j] }); j++; }
      else { rows.push({ op: '-', text: a2[i] }); i++; }
    }
  }
  for (const text of A.slice(A.length - suf)) rows.push({ op: ' ', text });
  return rows;
}

// The length of the longest common prefix of a and b (a binary search of
// native comparisons: a loop over each character of a large file runs
// cold, once per edit, and took tens of ms).
export function commonPrefix(a, b) {
  let lo = 0, hi = Math.min(a.length, b.length);
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (a.startsWith(b.slice(lo, mid), lo)) lo = mid; else hi = mid - 1;
  }
  return lo;
}
// The same for a common suffix, at most max long.
export function commonSuffix(a, b, max) {
  let lo = 0, hi = Math.max(0, max);
  while (lo < hi) {
    const mid = (lo + hi + 1) >> 1;
    if (a.endsWith(b.slice(b.length - mid, b.length - lo), a.length - lo)) lo = mid; else hi = mid - 1;
  }
  return lo;
}
