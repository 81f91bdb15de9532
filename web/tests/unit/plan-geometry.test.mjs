// plan-geometry.ts: the per-zoom simplification (Douglas–Peucker importance), tile culling, own dashes
// and waypoint numbers that draw a plan's 100 000-vertex paths fast (issue 11).
import assert from 'node:assert/strict';
import { test } from 'node:test';
import {
  buildPlanGeometry,
  clipSegment,
  dpImportance,
  dpSections,
  drawTile,
  keptVertices,
  LABEL_ZOOM,
  mercX,
  mercY,
  SECTION,
  tileLabels,
  traceDashes,
} from '../../src/plan-geometry.ts';

/** A deterministic pseudo-random walk: n vertices (x, y pairs), steps of about `step`. */
function walk(n, step = 1, seed = 7) {
  let s = seed;
  const rnd = () => ((s = (s * 1103515245 + 12345) % 2147483648) / 2147483648);
  const xy = new Float64Array(2 * n);
  let x = 0, y = 0, a = 0;
  for (let i = 0; i < n; i++) {
    xy[2 * i] = x;
    xy[2 * i + 1] = y;
    a += (rnd() - 0.5) * 2.5;
    x += Math.cos(a) * step * (0.2 + rnd());
    y += Math.sin(a) * step * (0.2 + rnd());
  }
  return xy;
}

function segDist(xy, p, a, b) {
  const ax = xy[2 * a], ay = xy[2 * a + 1], dx = xy[2 * b] - ax, dy = xy[2 * b + 1] - ay;
  const len2 = dx * dx + dy * dy;
  const t = len2 ? Math.max(0, Math.min(1, ((xy[2 * p] - ax) * dx + (xy[2 * p + 1] - ay) * dy) / len2)) : 0;
  return Math.hypot(xy[2 * p] - ax - t * dx, xy[2 * p + 1] - ay - t * dy);
}

/** Textbook recursive Douglas–Peucker: the kept indices. */
function dpReference(xy, a, b, tol, out = new Set([a, b])) {
  let best = -1, far = -1;
  for (let k = a + 1; k < b; k++) {
    const d = segDist(xy, k, a, b);
    if (d > far) [far, best] = [d, k];
  }
  if (best >= 0 && far > tol) {
    out.add(best);
    dpReference(xy, a, best, tol, out);
    dpReference(xy, best, b, tol, out);
  }
  return out;
}

test('importance thresholds give exactly Douglas–Peucker at every tolerance', () => {
  const xy = walk(300);
  const imp = new Float64Array(300);
  dpImportance(xy, 0, 299, imp);
  for (const tol of [0, 0.05, 0.3, 1, 2.5, 8, 40]) {
    const ref = [...dpReference(xy, 0, 299, tol)].sort((p, q) => p - q);
    assert.deepEqual(keptVertices(imp, 0, 299, tol), ref, `tolerance ${tol}`);
  }
});

test('simplified lines stay within the tolerance, keep their ends, and shrink as the tolerance grows', () => {
  const n = 2000;
  const xy = walk(n);
  const imp = new Float64Array(n);
  dpSections(xy, 0, n - 1, imp);
  let last = Infinity;
  for (const tol of [0.01, 0.1, 0.5, 1, 3, 10]) {
    const kept = keptVertices(imp, 0, n - 1, tol);
    assert.equal(kept[0], 0, 'first vertex kept');
    assert.equal(kept[kept.length - 1], n - 1, 'last vertex kept');
    // every section end is kept (the sections are culled one by one)
    for (let s = 0; s < n - 1; s += SECTION) assert.ok(kept.includes(s), `section start ${s}`);
    // error bound: each left-out vertex within tol of the kept segment that replaces it
    for (let j = 0; j + 1 < kept.length; j++)
      for (let k = kept[j] + 1; k < kept[j + 1]; k++) assert.ok(segDist(xy, k, kept[j], kept[j + 1]) <= tol + 1e-9, `vertex ${k} at tolerance ${tol}`);
    assert.ok(kept.length <= last, 'no more vertices at a larger tolerance');
    last = kept.length;
  }
  assert.ok(last < n / 20, `a 2000-vertex walk keeps ${last} vertices at 10 units`);
});

test('a staircase of 1-unit steps is a straight line from 2 units of tolerance on', () => {
  const n = 401;
  const xy = new Float64Array(2 * n);
  for (let i = 0; i < n; i++) {
    xy[2 * i] = Math.ceil(i / 2);
    xy[2 * i + 1] = Math.floor(i / 2);
  }
  const imp = new Float64Array(n);
  dpSections(xy, 0, n - 1, imp);
  const sectionEnds = Math.ceil((n - 1) / SECTION) + 1;
  assert.equal(keptVertices(imp, 0, n - 1, 1).length, sectionEnds);
  assert.equal(keptVertices(imp, 0, n - 1, 0.1).length, n);
});

test('Web Mercator as Leaflet: 0..256 at zoom 0, north up', () => {
  assert.equal(mercX(-180), 0);
  assert.equal(mercX(0), 128);
  assert.equal(mercX(180), 256);
  assert.ok(Math.abs(mercY(0) - 128) < 1e-9);
  assert.ok(mercY(40) < 128 && mercY(-40) > 128);
  assert.ok(Math.abs(mercY(85.0511287798) - 0) < 1e-6);
});

test('clipSegment and traceDashes: dashes only inside, with a phase that follows the line', () => {
  assert.deepEqual(clipSegment(-10, 5, 20, 0, [0, 0, 10, 10]), [0.5, 1]);
  assert.equal(clipSegment(-10, 20, 20, 0, [0, 0, 10, 10]), null);
  const calls = [];
  const ctx = { moveTo: (x, y) => calls.push(['M', x, y]), lineTo: (x, y) => calls.push(['L', x, y]) };
  // a 100-px line, pattern 6 on 5 off, seen through a window from x = 30 to 60
  const n = traceDashes(ctx, [0, 0, 100, 0], [6, 5], [30, -1, 60, 1]);
  const dashes = [];
  for (let i = 0; i < calls.length; i++) if (calls[i][0] === 'M') dashes.push([calls[i][1], calls[i + 1][1]]);
  assert.equal(n, dashes.length);
  // the pattern from x = 0: dashes at [0, 6], [11, 17], [22, 28], [33, 39], [44, 50], [55, 61], ...
  assert.deepEqual(
    dashes.map(([a, b]) => [+a.toFixed(6), +b.toFixed(6)]),
    [
      [33, 39],
      [44, 50],
      [55, 60],
    ],
  );
});

/** A recording 2D context: the points passed to moveTo/lineTo, and the calls. */
function recorder() {
  const r = { points: [], calls: {} };
  return new Proxy(r, {
    get(o, k) {
      if (k in o) return o[k];
      return (...a) => {
        o.calls[k] = (o.calls[k] ?? 0) + 1;
        if (k === 'moveTo' || k === 'lineTo') o.points.push(a);
        if (k === 'measureText') return { width: 6 * String(a[0]).length };
      };
    },
    set(o, k, v) {
      o[k] = v;
      return true;
    },
  });
}

/** A plan: a square area, one no-fly zone, two UAVs with a region each and a zig-zag path. */
function fixture() {
  const lon0 = 22.9, lat0 = 40.6, d = 0.00002; // ~2 m
  const P = (i, j) => [lon0 + i * d, lat0 + j * d];
  const square = (i0, j0, i1, j1) => [P(i0, j0), P(i1, j0), P(i1, j1), P(i0, j1), P(i0, j0)];
  const zig = (i0, n) => Array.from({ length: n }, (_, k) => P(i0 + (k % 2), k));
  const features = [
    { type: 'Feature', properties: { role: 'area' }, geometry: { type: 'Polygon', coordinates: [square(0, 0, 400, 400)] } },
    { type: 'Feature', properties: { role: 'no_fly_zone' }, geometry: { type: 'Polygon', coordinates: [square(180, 180, 220, 220)] } },
    { type: 'Feature', properties: { uav: 'a', kind: 'coverage', part: 0 }, geometry: { type: 'LineString', coordinates: zig(10, 400) } },
    { type: 'Feature', properties: { uav: 'a', kind: 'transit', part: 1 }, geometry: { type: 'LineString', coordinates: [P(11, 399), P(305, 10)] } },
    { type: 'Feature', properties: { uav: 'b', kind: 'coverage', part: 2 }, geometry: { type: 'LineString', coordinates: zig(300, 400) } },
  ];
  const plan = {
    uavs: [
      { id: 'a', region: { type: 'MultiPolygon', coordinates: [[square(0, 0, 200, 400)], [square(200, 0, 210, 10)]] } },
      { id: 'b', start: P(-5, -5), region: { type: 'MultiPolygon', coordinates: [[square(200, 0, 400, 400), square(250, 250, 260, 260)]] } },
    ],
  };
  return buildPlanGeometry(plan, { type: 'FeatureCollection', features });
}

test('buildPlanGeometry: counts, bounds, start and return points', () => {
  const { geometry: g, summary } = fixture();
  assert.deepEqual(
    summary.uavs.map((u) => [u.id, u.polygons, u.paths, u.waypoints]),
    [
      ['a', 2, 2, 401],
      ['b', 1, 1, 400],
    ],
  );
  const [[s, w], [n, e]] = summary.bounds;
  assert.ok(Math.abs(s - 40.6) < 1e-9 && Math.abs(w - 22.9) < 1e-9 && n > s && e > w);
  assert.ok(Math.abs(summary.uavs[1].start[1] - (22.9 - 5 * 0.00002)) < 1e-12, 'a given start is kept');
  assert.deepEqual(summary.uavs[0].start, [40.6, 22.9 + 10 * 0.00002], 'else the first path vertex');
  assert.equal(g.wpStart[2], 801);
  assert.equal(g.layers.length, 2 + 2 + 2 + 2, 'area, no-fly zones, 2 regions, 2 coverage, 2 transit layers');
});

/** The tiles of zoom z over the fixture's bounds. */
function tiles(summary, z) {
  const [[s, w], [n, e]] = summary.bounds;
  const t = (v) => Math.floor((v * 2 ** z) / 256);
  const out = [];
  for (let x = t(mercX(w)); x <= t(mercX(e)); x++) for (let y = t(mercY(n)); y <= t(mercY(s)); y++) out.push([x, y]);
  return out;
}

test('drawTile: fewer vertices zoomed out, a tile draws only its part zoomed in, no closePath', () => {
  const { geometry: g, summary } = fixture();
  const all = g.xy.length / 2;
  const perZoom = [];
  for (const z of [12, 15, 18, 20]) {
    let total = 0, most = 0;
    for (const [x, y] of tiles(summary, z)) {
      const ctx = recorder();
      const n = drawTile(ctx, g, z, x, y, 256);
      assert.equal(ctx.calls.closePath, undefined);
      total += n;
      most = Math.max(most, n);
    }
    perZoom.push(total);
    if (z === 20) assert.ok(most < all / 4, `zoom 20: a tile draws ${most} of ${all} vertices`);
  }
  // zoomed out, the 2 m zig-zags are below a pixel and drop out
  assert.ok(perZoom[0] < 120, `zoom 12 draws ${perZoom[0]} of ${all}`);
  for (let i = 1; i < perZoom.length; i++) assert.ok(perZoom[i] > perZoom[i - 1], `more detail at higher zoom: ${perZoom}`);
});

test('drawTile: a tile away from the plan draws nothing, the one under a path draws its colour', () => {
  const { geometry: g, summary } = fixture();
  const z = 17;
  const ctx = recorder();
  const [x, y] = tiles(summary, z)[0];
  assert.equal(drawTile(ctx, g, z, x - 5, y - 5, 256), 0);
  assert.equal(ctx.calls.stroke, undefined);
  let strokes = 0;
  for (const [tx, ty] of tiles(summary, z)) {
    const c = recorder();
    drawTile(c, g, z, tx, ty, 256);
    strokes += c.calls.stroke ?? 0;
  }
  assert.ok(strokes >= 8, 'the area, the no-fly zone, the regions and the paths are stroked');
});

test('waypoint numbers: none below LABEL_ZOOM; neighbouring tiles agree; all numbered when zoomed in', () => {
  const { geometry: g, summary } = fixture();
  const [x, y] = tiles(summary, LABEL_ZOOM - 1)[0];
  assert.deepEqual(tileLabels(g, LABEL_ZOOM - 1, x, y, 256), []);
  for (const z of [LABEL_ZOOM, 19, 22]) {
    const seen = new Map();
    for (const [tx, ty] of tiles(summary, z))
      for (const [u, k, px, py] of tileLabels(g, z, tx, ty, 256)) {
        // the same label in two tiles: at the same world position
        const key = `${u}:${k}`;
        const wx = px + tx * 256, wy = py + ty * 256;
        if (seen.has(key)) assert.deepEqual(seen.get(key).map((v) => +v.toFixed(6)), [wx, wy].map((v) => +v.toFixed(6)));
        seen.set(key, [wx, wy]);
      }
    if (z === 22) assert.equal(seen.size, 801, 'at zoom 22 (4 cm a pixel) every waypoint has its number');
    else assert.ok(seen.size > 0 && seen.size < 801, `zoom ${z}: ${seen.size} numbers (decluttered)`);
  }
});

test('parsePlan: the files as bytes; the page gets plan.json without its regions', async () => {
  const { parsePlan } = await import('../../src/plan-geometry.ts');
  const P = (i, j) => [22.9 + i * 1e-4, 40.6 + j * 1e-4];
  const region = { type: 'MultiPolygon', coordinates: [[[P(0, 0), P(1, 0), P(1, 1), P(0, 0)]]] };
  const plan = { uavs: [{ id: 'a', region, start: P(0, 0) }], coverage: { uavs: [{ id: 'a', poc: 0.9 }] } };
  const paths = { type: 'FeatureCollection', features: [{ type: 'Feature', properties: { uav: 'a', kind: 'coverage', part: 0 }, geometry: { type: 'LineString', coordinates: [P(0, 0), P(1, 1)] } }] };
  const bytes = (o) => new TextEncoder().encode(JSON.stringify(o)).buffer;
  const r = parsePlan(bytes(plan), bytes(paths));
  assert.equal(r.plan.uavs[0].region, undefined);
  assert.deepEqual(r.plan.uavs[0].start, P(0, 0));
  assert.deepEqual(r.plan.coverage, plan.coverage);
  assert.deepEqual([r.summary.uavs[0].polygons, r.summary.uavs[0].paths, r.summary.uavs[0].waypoints], [1, 1, 2]);
  assert.throws(() => parsePlan(bytes(plan), new TextEncoder().encode('{"type": ').buffer), SyntaxError);
});
