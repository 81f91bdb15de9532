// Linked share controls: integer percentages that always sum to 100. Pure functions (unit-tested).

function clean(x: number): number {
  return Number.isFinite(x) && x > 0 ? x : 0;
}

/**
 * Split `total` (a non-negative integer) into integers proportional to `weights` by the largest
 * remainder method, so they sum to exactly `total`. Non-positive or non-finite weights count as 0;
 * when every weight is 0 the split is equal (the first entries get the remainder).
 */
export function apportion(weights: number[], total: number): number[] {
  const n = weights.length;
  if (n === 0) return [];
  const t = Math.max(0, Math.round(total));
  const w = weights.map(clean);
  const max = Math.max(...w);
  // divide by the largest first: huge weights (1e308 twice) stay finite
  const eff = max > 0 && Number.isFinite(max) ? w.map((x) => x / max) : w.map(() => 1);
  const sum = eff.reduce((a, b) => a + b, 0);
  const exact = eff.map((x) => (x / sum) * t);
  const out = exact.map((x) => Math.floor(x));
  let left = t - out.reduce((a, b) => a + b, 0);
  const order = exact.map((x, i) => [x - out[i], i] as const).sort((a, b) => b[0] - a[0] || a[1] - b[1]);
  for (let k = 0; left > 0; k++, left--) out[order[k % n][1]]++;
  return out;
}

/** integer percentages proportional to the weights, summing to 100 (equal when all are 0) */
export function roundTo100(weights: number[]): number[] {
  return apportion(weights, 100);
}

/** equal integer shares of 100 for n UAVs (34/33/33) */
export function equalShares(n: number): number[] {
  return apportion(new Array(Math.max(0, n)).fill(1), 100);
}

/**
 * The operator sets share `index` to `value` %: it is clamped to 0..100 and rounded, and the other
 * shares are rescaled proportionally to their previous values so that all still sum to 100 (equally
 * when all the others were 0). One UAV always has 100.
 *
 * `locked` lists shares the operator set before (most recent first) that should keep their value:
 * the unlocked others absorb the change, proportionally; when they cannot (none left, or the locked
 * ones already exceed what is left), every other share is rescaled.
 */
export function setShare(shares: number[], index: number, value: number, locked: number[] = []): number[] {
  const n = shares.length;
  if (n === 0) return [];
  if (n === 1) return [100];
  if (index < 0 || index >= n || !Number.isFinite(value)) return roundTo100(shares);
  // every UAV keeps at least 1 %: the server refuses a share of 0 ("leave the UAV out instead"), so
  // 0 is not a value the operator can set here (issue 29, defect 7); remove the UAV instead
  const v = Math.min(100 - (n - 1), Math.max(MIN_SHARE, Math.round(value)));
  const cur = roundTo100(shares);
  const keep = new Set(locked.filter((i) => i !== index && i >= 0 && i < n));
  const free = cur.map((_, i) => i).filter((i) => i !== index && !keep.has(i));
  const keptSum = [...keep].reduce((a, i) => a + cur[i], 0);
  const out = cur.slice();
  out[index] = v;
  if (free.length > 0 && keptSum <= 100 - v) {
    const rest = apportion(
      free.map((i) => cur[i]),
      100 - v - keptSum,
    );
    free.forEach((i, k) => (out[i] = rest[k]));
    return atLeastOne(out, index);
  }
  const others = cur.map((_, i) => i).filter((i) => i !== index);
  const rest = apportion(
    others.map((i) => cur[i]),
    100 - v,
  );
  others.forEach((i, k) => (out[i] = rest[k]));
  return atLeastOne(out, index);
}

/** The smallest share a UAV can have, in %. */
export const MIN_SHARE = 1;

/** Raises every share but `index` to MIN_SHARE, taking from the largest of the others (sum kept). */
function atLeastOne(out: number[], index: number): number[] {
  for (let i = 0; i < out.length; i++) {
    if (i === index) continue;
    while (out[i] < MIN_SHARE) {
      let j = -1;
      for (let k = 0; k < out.length; k++) if (k !== index && k !== i && out[k] > MIN_SHARE && (j < 0 || out[k] > out[j])) j = k;
      if (j < 0) break;
      out[j]--;
      out[i]++;
    }
  }
  return out;
}

/**
 * The shares to keep when the operator edits `index`, from the indexes edited before (most recent
 * first): at most n − 2 of them, so at least one other share can absorb the change.
 */
export function lockedFor(history: number[], index: number, n: number): number[] {
  const out: number[] = [];
  for (const i of history) {
    if (out.length >= n - 2) break;
    if (i !== index && i >= 0 && i < n && !out.includes(i)) out.push(i);
  }
  return out;
}

/**
 * Shares as the mission file gives them (fractions or any weights, some possibly absent) as integer
 * percentages: given ones are normalised when all are given; otherwise the absent ones split what is
 * left of 1 (the library's rule).
 */
export function sharesFromDoc(shares: (number | undefined | null)[]): number[] {
  const n = shares.length;
  if (n === 0) return [];
  const given = shares.map((s) => (typeof s === 'number' && Number.isFinite(s) && s > 0 ? s : undefined));
  const missing = given.filter((s) => s === undefined).length;
  if (missing === 0) return roundTo100(given as number[]);
  const sum = given.reduce<number>((a, s) => a + (s ?? 0), 0);
  const each = sum < 1 ? (1 - sum) / missing : 0;
  return roundTo100(given.map((s) => s ?? each));
}

/** the shares the mission document stores: fractions of 1 */
export function toFractions(percent: number[]): number[] {
  return percent.map((p) => p / 100);
}
