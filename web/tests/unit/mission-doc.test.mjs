import { test } from 'node:test';
import assert from 'node:assert/strict';
import {
  areaPolygons,
  classify,
  docBbox,
  fileName,
  geojsonPolygons,
  matchField,
  newDraft,
  nextUavId,
  nfzPolygons,
  withArea,
  withNfz,
} from '../../src/mission-doc.ts';
import { readImport } from '../../src/import.ts';

/** a closed square ring of side d at (x, y), as a polygon */
const sq = (x, y, d) => [
  [
    [x, y],
    [x + d, y],
    [x + d, y + d],
    [x, y + d],
    [x, y],
  ],
];

test('area and no-fly zones in and out of the document', () => {
  let doc = newDraft();
  assert.deepEqual(areaPolygons(doc), []);
  doc = withArea(doc, [sq(22.9, 40.6, 0.01)]);
  assert.equal(doc.area.type, 'Polygon');
  doc = withArea(doc, [sq(22.9, 40.6, 0.01), sq(23, 40.6, 0.01)]);
  assert.equal(doc.area.type, 'MultiPolygon');
  assert.equal(areaPolygons(doc).length, 2);
  doc = withNfz(doc, [sq(22.902, 40.602, 0.001)]);
  assert.equal(nfzPolygons(doc).length, 1);
  assert.deepEqual(docBbox(doc), [22.9, 40.6, 23.01, 40.61]);
  assert.equal(withArea(doc, []).area, undefined);
  assert.equal(docBbox(newDraft()), null);
  assert.deepEqual(newDraft('x', 0).uavs, []);
  assert.deepEqual(newDraft('x', 2).uavs, [{ id: 'uav1' }, { id: 'uav2' }]);
});

test('a Feature-wrapped area and MultiPolygon zones are read', () => {
  const doc = {
    area: { type: 'Feature', properties: {}, geometry: { type: 'Polygon', coordinates: sq(1, 2, 1) } },
    no_fly_zones: [{ type: 'MultiPolygon', coordinates: [sq(1.1, 2.1, 0.1), sq(1.5, 2.5, 0.1)] }],
  };
  assert.equal(areaPolygons(doc).length, 1);
  assert.equal(nfzPolygons(doc).length, 2);
});

test('the largest polygon is the area, polygons inside it are no-fly zones', () => {
  const r = classify([{ coords: sq(22.905, 40.605, 0.001) }, { coords: sq(22.9, 40.6, 0.01) }, { coords: sq(23.1, 40.6, 0.005) }]);
  assert.equal(r.area.length, 2);
  assert.deepEqual(r.area[0], sq(22.9, 40.6, 0.01));
  assert.deepEqual(r.nfz, [sq(22.905, 40.605, 0.001)]);
});

test('features marked as no-fly zones are zones whatever their size', () => {
  const fc = {
    type: 'FeatureCollection',
    features: [
      { type: 'Feature', properties: { role: 'no_fly_zone' }, geometry: { type: 'Polygon', coordinates: sq(0, 0, 5) } },
      { type: 'Feature', properties: { name: 'field' }, geometry: { type: 'Polygon', coordinates: sq(0, 0, 1) } },
      { type: 'Feature', properties: { role: 'NFZ' }, geometry: { type: 'Point', coordinates: [0, 0] } },
    ],
  };
  const polys = geojsonPolygons(fc);
  assert.equal(polys.length, 2);
  const r = classify(polys);
  assert.deepEqual(r.area, [sq(0, 0, 1)]);
  assert.deepEqual(r.nfz, [sq(0, 0, 5)]);
});

test('server field paths find their input', () => {
  const anchors = ['area', 'no_fly_zones', 'camera.side_overlap', 'camera', 'uavs[1].share', 'uavs[1]', 'planner_params.max_iterations'];
  assert.equal(matchField('camera.side_overlap', anchors), 'camera.side_overlap');
  assert.equal(matchField('camera.hfov_deg', anchors), 'camera');
  assert.equal(matchField('area.coordinates[0]', anchors), 'area');
  assert.equal(matchField('uavs[1].share', anchors), 'uavs[1].share');
  assert.equal(matchField('uavs[1].start', anchors), 'uavs[1]');
  assert.equal(matchField('uavs[10].start', anchors), null);
  assert.equal(matchField('areas', anchors), null);
  assert.equal(matchField('body', anchors), null);
  assert.equal(matchField('', anchors), null);
});

test('file names and UAV ids', () => {
  assert.equal(fileName('North olive grove'), 'North olive grove.json');
  assert.equal(fileName('../etc/pass:wd'), '_etc_pass_wd.json');
  assert.equal(fileName(''), 'mission.json');
  assert.equal(fileName(undefined), 'mission.json');
  assert.equal(nextUavId(['uav1', 'UAV2']), 'uav3');
  assert.equal(nextUavId([]), 'uav1');
});

test('import: mission files go to the server as they are', () => {
  const m = readImport('{"area": {"type": "Polygon", "coordinates": []}, "uavs": 2}', 'a.json');
  assert.equal(m.kind, 'mission');
  assert.equal(m.kind === 'mission' && m.format, 'uavcover');
  const d = readImport('{"droneNo": 2, "polygon": []}', 'b.json');
  assert.equal(d.kind === 'mission' && d.format, 'mcpp');
});

test('import: GeoJSON gives a draft with defaults', () => {
  const text = JSON.stringify({
    type: 'FeatureCollection',
    features: [
      { type: 'Feature', properties: {}, geometry: { type: 'Polygon', coordinates: sq(22.9, 40.6, 0.01) } },
      { type: 'Feature', properties: {}, geometry: { type: 'Polygon', coordinates: sq(22.905, 40.605, 0.001) } },
    ],
  });
  const r = readImport(text, '/x/My field.geojson');
  assert.equal(r.kind, 'draft');
  if (r.kind !== 'draft') return;
  assert.equal(r.doc.name, 'My field');
  assert.equal(areaPolygons(r.doc).length, 1);
  assert.equal(nfzPolygons(r.doc).length, 1);
  assert.equal(r.doc.spacing_m, 20);
  assert.equal(r.doc.altitude_m, 40);
  assert.deepEqual(r.doc.uavs, [{ id: 'uav1' }]);
});

test('import: a lone Feature names the mission', () => {
  const f = { type: 'Feature', properties: { name: 'Vineyard' }, geometry: { type: 'Polygon', coordinates: sq(1, 2, 1) } };
  const r = readImport(JSON.stringify(f), 'x.geojson');
  assert.equal(r.kind === 'draft' && r.doc.name, 'Vineyard');
});

test('import: bad files are refused in words', () => {
  assert.throws(() => readImport('{not json', 'x.json'), /x.json: neither JSON nor KML/);
  assert.throws(() => readImport('[1,2]', 'x.json'), /a JSON object is expected/);
  assert.throws(() => readImport('{"type": "Point", "coordinates": [0, 0]}', 'p.geojson'), /no Polygon/);
  assert.throws(() => readImport('{"hello": 1}', 'h.json'), /not a uavcover mission/);
  assert.throws(() => readImport('<kml/>', 'k.kml'), /KML cannot be read here/);
});
