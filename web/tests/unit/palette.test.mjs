// palette.ts: the CLI's colours (src/render/canvas.cpp uav_colour), in order.
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { test } from 'node:test';
import { PALETTE, uavColour } from '../../src/palette.ts';

test('the palette is canvas.cpp\'s, in order', () => {
  const cpp = readFileSync(new URL('../../../src/render/canvas.cpp', import.meta.url), 'utf8');
  const block = cpp.slice(cpp.indexOf('Rgb uav_colour('));
  const body = block.slice(block.indexOf('{', block.indexOf('palette[]')), block.indexOf('};'));
  const triples = [...body.matchAll(/\{([\d.]+),\s*([\d.]+),\s*([\d.]+)\}/g)].map((m) => m.slice(1, 4).map(Number));
  assert.equal(triples.length, 10);
  assert.deepEqual(PALETTE.map((c) => [...c]), triples);
});

test('colours: first round as given, later rounds darker', () => {
  assert.equal(uavColour(0), '#1f78b5');
  assert.equal(uavColour(1), '#ff800d');
  assert.notEqual(uavColour(10), uavColour(0));
  assert.equal(uavColour(10), '#12486d'); // x0.6
  assert.equal(new Set(Array.from({ length: 10 }, (_, i) => uavColour(i))).size, 10);
});
