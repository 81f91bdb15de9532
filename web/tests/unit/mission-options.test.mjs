// The structure, oblique, wind, objective and capability-share blocks of the mission document
// (docs/patterns.md, docs/mission-format.md) as the Define tab edits them.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  docBbox,
  newDraft,
  obliqueOf,
  sharesAuto,
  structureOf,
  terrainOf,
  windOf,
  withTerrain,
  withArea,
  withCorridor,
  withOblique,
  withPattern,
  withSharesAuto,
  withStructure,
  withWind,
} from '../../src/mission-doc.ts';

const ring = [
  [22.9, 40.6],
  [22.9003, 40.6],
  [22.9003, 40.6002],
  [22.9, 40.6002],
  [22.9, 40.6],
];

test('a structure replaces the area and the corridor; safe height only when not the default', () => {
  let doc = withArea(newDraft(), [[ring]]);
  doc = withCorridor(doc, [[22.9, 40.6], [22.91, 40.6]], 50);
  doc = withStructure(doc, { footprint: [ring], height_m: 40, standoff_m: 15, top: true, safe_height_m: 5 });
  assert.equal(doc.area, undefined);
  assert.equal(doc.corridor, undefined);
  assert.deepEqual(doc.structure, { footprint: { type: 'Polygon', coordinates: [ring] }, height_m: 40, standoff_m: 15, top: true });
  assert.deepEqual(structureOf(doc), { footprint: [ring], height_m: 40, standoff_m: 15, top: true, safe_height_m: 5 });
  assert.deepEqual(docBbox(doc), [22.9, 40.6, 22.9003, 40.6002]);
  doc = withStructure(doc, { ...structureOf(doc), safe_height_m: 8 });
  assert.equal(doc.structure.safe_height_m, 8);
  assert.equal(structureOf(withStructure(doc, null)), null);
  // a footprint that is not one polygon is no structure
  assert.equal(structureOf({ structure: { footprint: { type: 'Point', coordinates: [1, 2] }, height_m: 3 } }), null);
});

test('obliques: every field written, removing them keeps the other pattern options', () => {
  let doc = withPattern(newDraft(), { crosshatch: true });
  assert.equal(obliqueOf(doc), null);
  doc = withOblique(doc, { gimbal_pitch_deg: -30, directions: 2, nadir: false });
  assert.deepEqual(doc.pattern, { crosshatch: true, oblique: { gimbal_pitch_deg: -30, directions: 2, nadir: false } });
  assert.deepEqual(obliqueOf(doc), { gimbal_pitch_deg: -30, directions: 2, nadir: false });
  // a partial block reads with the defaults
  assert.deepEqual(obliqueOf({ pattern: { oblique: { directions: 1 } } }), { gimbal_pitch_deg: -45, directions: 1, nadir: true });
  doc = withOblique(doc, null);
  assert.deepEqual(doc.pattern, { crosshatch: true });
});

test('wind: a calm wind is no block, the direction is normalised', () => {
  let doc = withWind(newDraft(), { speed_mps: 8, from_deg: 450 });
  assert.deepEqual(doc.wind, { speed_mps: 8, from_deg: 90 });
  assert.deepEqual(windOf(doc), { speed_mps: 8, from_deg: 90 });
  assert.deepEqual(withWind(doc, { speed_mps: 5, from_deg: -90 }).wind, { speed_mps: 5, from_deg: 270 });
  assert.equal(withWind(doc, { speed_mps: 0, from_deg: 10 }).wind, undefined);
  assert.equal(withWind(doc, null).wind, undefined);
});

test('shares from capabilities: every UAV auto, or none', () => {
  let doc = { ...newDraft('m', 3) };
  doc.uavs = [{ id: 'a', share: 0.5 }, { id: 'b', share: 0.3 }, { id: 'c' }];
  assert.equal(sharesAuto(doc), false);
  doc = withSharesAuto(doc, true);
  assert.deepEqual(doc.uavs.map((u) => u.share), ['auto', 'auto', 'auto']);
  assert.equal(sharesAuto(doc), true);
  doc = withSharesAuto(doc, false);
  assert.deepEqual(doc.uavs.map((u) => u.share), [undefined, undefined, undefined]);
  assert.equal(sharesAuto({ uavs: [] }), false);
});

test('terrain (issue 31): a stored DEM or the server tiles, follow, tolerance and climb limit round-trip', () => {
  const doc = { name: 'm', area: {}, uavs: 1 };
  assert.deepEqual(terrainOf(doc), { source: { kind: 'none' }, follow: true, tolerance_m: 1 });
  const withDem = withTerrain(doc, { source: { kind: 'dem', dem_id: 7 }, follow: true, tolerance_m: 2, max_climb_mps: 1.5, max_descent_mps: 1.5 });
  assert.deepEqual(withDem.terrain, { dem_id: 7, mode: 'follow', tolerance_m: 2, max_climb_mps: 1.5, max_descent_mps: 1.5 });
  assert.deepEqual(terrainOf(withDem), { source: { kind: 'dem', dem_id: 7 }, follow: true, tolerance_m: 2, max_climb_mps: 1.5, max_descent_mps: 1.5 });
  const tiles = withTerrain(doc, { source: { kind: 'server' }, follow: false, tolerance_m: 1 });
  assert.deepEqual(tiles.terrain, { source: 'server', mode: 'off', tolerance_m: 1 });
  assert.equal(terrainOf(tiles).follow, false);
  assert.equal('terrain' in withTerrain(withDem, { source: { kind: 'none' }, follow: true, tolerance_m: 1 }), false);
  // a file path (the CLI's) reads as none: the server refuses it
  assert.deepEqual(terrainOf({ terrain: { dem: 'hill.tif' } }).source, { kind: 'none' });
});
