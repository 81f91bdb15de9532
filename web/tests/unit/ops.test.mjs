// Issue 29's pure pieces: warnings for people, field names as the form names them, the source document
// edited for a stored mission, a UAV's progress with reassigned work, and a flight's end in words.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { groupWarnings, humanNumber, humanText } from '../../src/warnings.ts';
import { editableDoc, fieldLabel, humanMessage } from '../../src/mission-doc.ts';
import { flightOutcome, progressText, uavWork } from '../../src/fly-model.ts';

test('warnings: numbers rounded for people, repeats grouped in first-seen order', () => {
  assert.equal(humanNumber('119.99000000000001'), '119.99');
  assert.equal(humanNumber('3.14159265'), '3.1416');
  assert.equal(humanNumber('59.999999999'), '60');
  assert.equal(humanText('step compressed from 60 m to 59.999999999 m (60..119.99000000000001 m)'), 'step compressed from 60 m to 60 m (60..119.99 m)');
  assert.equal(humanText('uav 2 at 40.6012345 N'), 'uav 2 at 40.601 N');
  const w = ['b 1.000001', 'a', 'b 1.0000011', 'a', 'c'];
  const g = groupWarnings(w);
  assert.deepEqual(g.map((x) => [x.text, x.count]), [['b 1', 2], ['a', 2], ['c', 1]]);
  assert.deepEqual(g[0].raw, ['b 1.000001', 'b 1.0000011']);
  assert.equal(g.reduce((n, x) => n + x.count, 0), w.length);
  assert.deepEqual(groupWarnings([]), []);
});

test('field paths as the form names them', () => {
  const doc = { uavs: [{ id: 'alpha' }, { id: 'bravo' }, {}] };
  assert.equal(fieldLabel('uavs[1].share', doc), 'bravo share');
  assert.equal(fieldLabel('uavs[2].speed_mps', doc), 'uav3 speed');
  assert.equal(fieldLabel('uavs[0]', doc), 'alpha');
  assert.equal(fieldLabel('uavs[1].camera.altitude_m', doc), 'bravo camera altitude');
  assert.equal(fieldLabel('camera.altitude_m'), 'Altitude');
  assert.equal(fieldLabel('camera.side_overlap'), 'Side overlap');
  assert.equal(fieldLabel('area.coordinates[0]'), 'Area, polygon 1');
  assert.equal(fieldLabel('area'), 'Area');
  assert.equal(fieldLabel('no_fly_zones[2]'), 'No-fly zone 3');
  assert.equal(fieldLabel('planner_params.max_iterations'), 'Planner parameter max_iterations');
  assert.equal(fieldLabel(''), '');
  assert.equal(fieldLabel('something.else'), 'something.else');
  assert.equal(humanMessage('uavs[1].share', 'uavs[1].share: must be positive', doc), 'must be positive');
  assert.equal(humanMessage('uavs', 'uavs[0].share and uavs[1].share are zero', doc), 'alpha share and bravo share are zero');
  assert.equal(humanMessage('area', 'area.coordinates[0] crosses itself'), 'Area, polygon 1 crosses itself');
});

test('a stored mission is edited from its source when that is a uavcover document (catalog ids kept)', () => {
  const mission = { name: 'n', area: {}, uavs: [{ id: 'a', speed_mps: 12 }] };
  const source = { name: 'n', area: {}, uavs: [{ id: 'a', catalog_id: 3 }] };
  assert.equal(editableDoc({ mission, source }), source);
  assert.equal(editableDoc({ mission, source: { droneNo: 2, polygon: [] } }), mission, 'an mCPP input: the normalised mission');
  assert.equal(editableDoc({ mission }), mission);
  assert.equal(editableDoc({ mission, source: [1] }), mission);
});

test('progress counts reassigned work; a flight with a lost UAV does not end plainly "done"', () => {
  const helper = { waypoints: 'RRRRRRRRRRRRR', progress: 1, missions: [{ kind: 'sortie' }, { kind: 'reassigned', waypoints: 'RRPPPPPPPPPPPPP' }] };
  assert.deepEqual(uavWork(helper), { ownReached: 13, own: 13, extraReached: 2, extra: 15 });
  const p = progressText(helper);
  assert.equal(p.text, '53.6 % (13/13 own, 2/15 reassigned)');
  assert.ok(Math.abs(p.fraction - 15 / 28) < 1e-12);
  assert.equal(progressText({ waypoints: 'RRPP', progress: 0.5 }).text, '50.0 % (2/4)');

  const uav = (id, link, alt) => ({ uav: id, phase: 'landed', link: { state: link }, position: { lon: 0, lat: 0, alt_m: alt } });
  const done = { state: 'done', uavs: [uav('A', 'ok', 0), uav('B', 'lost', 50)], alerts: [{ kind: 'link_lost', uav: 'B', active: true }] };
  assert.deepEqual(flightOutcome(done), { outcome: 'done-lost', text: 'done with a lost UAV: B (last seen at 50 m)', lost: ['B'] });
  assert.equal(flightOutcome({ state: 'done', uavs: [uav('A', 'ok', 0)], alerts: [] }).text, 'done');
  assert.equal(flightOutcome({ ...done, state: 'flying' }).text, 'flying');
  // the alert still active is enough
  assert.equal(flightOutcome({ state: 'aborted', uavs: [uav('A', 'ok', 3)], alerts: [{ kind: 'link_lost', uav: 'A', active: true }] }).outcome, 'aborted-lost');
});
