// The corridor and pattern blocks of the mission document (docs/patterns.md) as the Define tab edits them.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { corridorOf, docBbox, newDraft, patternOf, withArea, withCorridor, withPattern } from '../../src/mission-doc.ts';

const line = [
  [10, 45],
  [10.01, 45],
  [10.02, 45.005],
];

test('a corridor replaces the area, and back', () => {
  let doc = withArea(newDraft(), [[[[10, 45], [10.1, 45], [10.1, 45.1], [10, 45]]]]);
  assert.ok(doc.area);
  doc = withCorridor(doc, line, 120);
  assert.equal(doc.area, undefined);
  assert.deepEqual(doc.corridor, { line: { type: 'LineString', coordinates: line }, width_m: 120 });
  assert.deepEqual(corridorOf(doc), { line, width_m: 120 });
  assert.deepEqual(docBbox(doc), [10, 45, 10.02, 45.005]);
  doc = withCorridor(doc, null, 0);
  assert.equal(doc.corridor, undefined);
  assert.equal(corridorOf(doc), null);
});

test('pattern options: defaults are not written, other fields are kept', () => {
  let doc = newDraft();
  assert.equal(patternOf(doc), null);
  doc = withPattern(doc, { crosshatch: true, turnaround_m: 10, entry: 'auto' });
  assert.deepEqual(doc.pattern, { crosshatch: true, turnaround_m: 10 });
  doc = { ...doc, pattern: { ...doc.pattern, oblique: { directions: 4 } } };
  doc = withPattern(doc, { crosshatch: false, entry: 'ne' });
  assert.deepEqual(doc.pattern, { turnaround_m: 10, entry: 'ne', oblique: { directions: 4 } });
  assert.deepEqual(patternOf(doc), { crosshatch: false, turnaround_m: 10, entry: 'ne', alternate_transects: false, capture_in_turnaround: false });
  assert.equal(withPattern(doc, null).pattern, undefined);
});

test('the facade picture: one pixel per sample, colours by views (3+ capped), corners dark', async () => {
  const { facadePixels, VIEW_COLOURS } = await import('../../src/facade-view.ts');
  const px = facadePixels({ cols: 4, rows: 2, wall_start_col: [0, 2], views: ['0129', '3300'] });
  const at = (r, c) => Array.from(px.slice((r * 4 + c) * 4, (r * 4 + c) * 4 + 3));
  assert.deepEqual(at(0, 0), VIEW_COLOURS[0]);
  assert.deepEqual(at(0, 1), VIEW_COLOURS[1]);
  assert.deepEqual(at(0, 2), [40, 40, 40], 'the second wall starts at column 2');
  assert.deepEqual(at(0, 3), VIEW_COLOURS[3], '9 views: 3+');
  assert.deepEqual(at(1, 0), VIEW_COLOURS[3]);
  assert.deepEqual(at(1, 3), VIEW_COLOURS[0]);
  assert.equal(px[3], 255);
});
