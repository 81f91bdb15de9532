import { test } from 'node:test';
import assert from 'node:assert/strict';
import { effectiveLimit, LIMIT_FIELDS, limitsSummary } from '../../src/uav-limits.ts';

const field = (k) => LIMIT_FIELDS.find((f) => f.key === k);

test('a UAV without limits flies the server defaults', () => {
  assert.equal(effectiveLimit({}, field('endurance_min')), 25);
  assert.equal(effectiveLimit({}, field('climb_mps')), 3);
  assert.equal(effectiveLimit({}, field('descent_mps')), 1.5);
  assert.equal(effectiveLimit({}, field('max_accel_mps2')), 2);
  assert.equal(limitsSummary({}), '25 min · climb 3 m/s · descent 1.5 m/s');
});

test('its own values win, then the catalog endurance, and are marked', () => {
  assert.equal(effectiveLimit({ endurance_min: 40 }, field('endurance_min'), 30), 40);
  assert.equal(effectiveLimit({}, field('endurance_min'), 30), 30);
  // the catalog gives an endurance only
  assert.equal(effectiveLimit({}, field('climb_mps'), 30), 3);
  assert.equal(limitsSummary({ climb_mps: 5, descent_mps: 2 }, 42), '42 min · climb 5 m/s* · descent 2 m/s*');
});

test('the ranges are the mission reader ones (src/mission/input_v1.cpp)', () => {
  assert.deepEqual(
    LIMIT_FIELDS.map((f) => [f.key, f.min, f.max]),
    [
      ['endurance_min', 0.1, 10000],
      ['max_accel_mps2', 0.001, 100],
      ['climb_mps', 0.1, 30],
      ['descent_mps', 0.1, 30],
    ],
  );
});
