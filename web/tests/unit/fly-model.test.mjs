import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  buildReplay,
  changedIndices,
  countStatus,
  failSpec,
  formatEta,
  planWaypoints,
  positionAt,
  statusesAt,
  statusOf,
  bearing,
} from '../../src/fly-model.ts';

const line = (uav, kind, part, coords) => ({ type: 'Feature', properties: { uav, kind, part }, geometry: { type: 'LineString', coordinates: coords } });

test('coverage waypoints: every vertex of the coverage parts, in part order, transits apart', () => {
  const paths = {
    type: 'FeatureCollection',
    features: [
      { type: 'Feature', properties: { role: 'area', index: 0 }, geometry: { type: 'Polygon', coordinates: [] } },
      // parts listed out of order: the "part" number decides
      line('A', 'coverage', 2, [[21.3, 39.3], [21.4, 39.4]]),
      line('A', 'transit', 1, [[21.2, 39.2], [21.3, 39.3]]),
      line('A', 'coverage', 0, [[21.0, 39.0], [21.1, 39.1], [21.2, 39.2]]),
      line('B', 'coverage', 0, [[22.0, 40.0], [22.0, 40.0], [22.1, 40.1]]),
    ],
  };
  const w = planWaypoints(paths);
  assert.deepEqual([...w.keys()], ['A', 'B']);
  // global indices 0..4: part 0's three vertices, then part 2's two (the transit adds none); [lat, lon]
  assert.deepEqual(w.get('A').waypoints, [[39.0, 21.0], [39.1, 21.1], [39.2, 21.2], [39.3, 21.3], [39.4, 21.4]]);
  assert.equal(w.get('A').transit.length, 1);
  assert.equal(w.get('A').coverage.length, 2);
  // a repeated vertex is a waypoint of its own, as sorties::coverage_waypoints counts them
  assert.equal(w.get('B').waypoints.length, 3);
});

test('status characters, counts and changed indices', () => {
  assert.equal(statusOf('reached'), 'R');
  assert.equal(statusOf('C'), 'C');
  assert.equal(statusOf('skipped'), 'S');
  assert.equal(statusOf('pending'), 'P');
  assert.equal(statusOf('x'), null);
  assert.equal(statusOf(3), null);
  assert.equal(countStatus('RRCPPS', 'R'), 2);
  assert.equal(countStatus(undefined, 'R'), 0);
  assert.deepEqual(changedIndices('RRCPP', 'RRRCP'), [2, 3]);
  assert.deepEqual(changedIndices('PP', 'PP'), []);
  assert.deepEqual(changedIndices('P', 'PPP'), [0, 1, 2], 'another length: all');
});

test('the failure of a simulated UAV as simulate --fail', () => {
  assert.equal(failSpec(0, 40, 'link'), null, 'no UAV chosen: no failure');
  assert.equal(failSpec(2, 40, 'link'), '2@0.4:link');
  assert.equal(failSpec(1, 12.5, 'land'), '1@0.125:land');
  assert.equal(failSpec(3, 100, ''), '3@1');
  assert.throws(() => failSpec(2, 120, 'link'), /between 0 and 100/);
  assert.throws(() => failSpec(2, NaN, 'link'), /between 0 and 100/);
});

test('ETA in words', () => {
  assert.equal(formatEta(null), '—');
  assert.equal(formatEta(-1), '—');
  assert.equal(formatEta(45.4), '45 s');
  assert.equal(formatEta(185), '3 min 05 s');
  assert.equal(formatEta(3 * 3600 + 120), '3 h 02 min');
});

test('bearing: north 0, east 90, south 180, west 270', () => {
  assert.ok(Math.abs(bearing([39, 21], [39.01, 21]) - 0) < 1e-6);
  assert.ok(Math.abs(bearing([39, 21], [39, 21.01]) - 90) < 0.01);
  assert.ok(Math.abs(bearing([39, 21], [38.99, 21]) - 180) < 1e-6);
  assert.ok(Math.abs(bearing([39, 21], [39, 20.99]) - 270) < 0.01);
});

const t = (s) => new Date(Date.UTC(2026, 10, 26, 8, 0, s)).toISOString();

test('replay: positions interpolated between telemetry records, heading from the direction of travel', () => {
  const records = [
    { seq: 3, t: t(2), uav: 'A', kind: 'telemetry', data: { lat: 39.002, lon: 21.0, alt_m: 40 } },
    { seq: 1, t: t(0), uav: 'A', kind: 'telemetry', data: { lat: 39.0, lon: 21.0, alt_m: 40 } },
    { seq: 2, t: t(1), uav: 'B', kind: 'telemetry', data: { position: { lat: 40, lon: 22, heading_deg: 45 } } },
    { seq: 4, t: t(1), uav: '', kind: 'state', data: { state: 'flying' } },
    { seq: 5, t: t(1), uav: 'A', kind: 'telemetry', data: { lat: 'bad' } },
  ];
  const r = buildReplay(records, new Map([['A', 3], ['B', 2]]));
  assert.equal(r.t1 - r.t0, 2000);
  const a = r.uavs.get('A');
  assert.equal(a.track.length, 2, 'sorted by time; the record without a position is left out');
  const mid = positionAt(a, r.t0 + 500);
  assert.ok(Math.abs(mid.lat - 39.0005) < 1e-9, `a quarter of the way: ${mid.lat}`);
  assert.ok(Math.abs(mid.heading) < 1e-6, 'flying north');
  assert.equal(mid.count, 1);
  const before = positionAt(a, r.t0 - 1000);
  assert.equal(before.lat, 39.0);
  const after = positionAt(a, r.t1 + 1000);
  assert.equal(after.lat, 39.002);
  assert.equal(after.count, 2);
  assert.equal(positionAt(r.uavs.get('B'), r.t1).heading, 45, 'the reported heading');
  assert.deepEqual(r.events.map((e) => e.text), ['flying']);
});

test('replay: waypoint statuses at any time', () => {
  const wp = (seq, s, uav, index, status) => ({ seq, t: t(s), uav, kind: 'waypoint', data: { waypoint: index, status } });
  const records = [
    wp(1, 0, 'A', 0, 'current'),
    wp(2, 1, 'A', 0, 'reached'),
    wp(3, 1, 'A', 1, 'current'),
    wp(4, 2, 'A', 1, 'reached'),
    wp(5, 2, 'A', 2, 'current'),
    { seq: 6, t: t(3), uav: 'A', kind: 'waypoint', data: { index: 2, status: 'S' } },
    { seq: 7, t: t(3), uav: 'A', kind: 'waypoint', data: { waypoint: 1, status: 'R', reassignment: 1 } },
    wp(8, 3, 'A', -1, 'reached'),
  ];
  const r = buildReplay(records, new Map([['A', 4]]));
  const a = r.uavs.get('A');
  assert.equal(statusesAt(a, r.t0 - 1), 'PPPP');
  assert.equal(statusesAt(a, r.t0), 'CPPP');
  assert.equal(statusesAt(a, r.t0 + 1500), 'RCPP');
  assert.equal(statusesAt(a, r.t0 + 2000), 'RRCP');
  assert.equal(statusesAt(a, r.t1), 'RRSP', 'the reassigned mission and the bad index are left out');
  // the same second: seq decides (reached before the next one's current)
  const same = buildReplay([wp(2, 0, 'A', 0, 'reached'), wp(1, 0, 'A', 0, 'current')], new Map([['A', 1]]));
  assert.equal(statusesAt(same.uavs.get('A'), same.t1), 'R');
});

test('photo uploads: heads of at most 256 KiB, batches under 8 MiB and 200 parts, in order', async () => {
  const { photoBatches, HEAD_BYTES, BATCH_BYTES, BATCH_PARTS } = await import('../../src/fly-model.ts');
  assert.deepEqual(photoBatches([]), []);
  // 8 MiB / 256 KiB = 32 heads of big files per batch
  const big = new Array(70).fill(9e6);
  const b = photoBatches(big);
  assert.deepEqual(b.map((g) => g.length), [32, 32, 6]);
  assert.deepEqual(b.flat(), [...big.keys()]);
  for (const g of b) assert.ok(g.reduce((s, i) => s + Math.min(big[i], HEAD_BYTES), 0) <= BATCH_BYTES);
  // small files: the part limit
  const small = new Array(450).fill(1000);
  assert.deepEqual(photoBatches(small).map((g) => g.length), [BATCH_PARTS, BATCH_PARTS, 50]);
  // one file larger than a batch still goes (its head)
  assert.deepEqual(photoBatches([1e9], HEAD_BYTES, 100), [[0]]);
});

test('a card says the waypoint retries: none, the one being retried of the limit, then the total', async () => {
  const { retriesText } = await import('../../src/fly-model.ts');
  assert.deepEqual(retriesText(undefined), { text: 'none', state: 'ok' });
  assert.deepEqual(retriesText({ waypoint: null, count: 0, total: 0 }, 2), { text: 'none', state: 'ok' });
  assert.deepEqual(retriesText({ waypoint: 7, count: 1, total: 1 }, 2), { text: 'waypoint 7: 1 of 2 (1 in all)', state: 'retrying' });
  assert.deepEqual(retriesText({ waypoint: 7, count: 2, total: 3 }), { text: 'waypoint 7: 2 (3 in all)', state: 'retrying' });
  assert.deepEqual(retriesText({ waypoint: null, count: 0, total: 3 }, 2), { text: '3 in all', state: 'ok' });
});
