import { test } from 'node:test';
import assert from 'node:assert/strict';
import { latestDone, planLabel } from '../../src/plan-history.ts';

const plan = (id, state, extra = {}) => ({
  id,
  revision: 2,
  state,
  planner: 'darp',
  params: { planner: 'darp' },
  created: '2026-11-26T10:00:00.000Z',
  finished: state === 'done' ? '2026-11-26T10:01:00.000Z' : null,
  metrics: state === 'done' ? { poc: 0.98123 } : {},
  ...extra,
});

test('the plan opened with a mission is the newest done one', () => {
  const items = [plan(9, 'running'), plan(8, 'failed'), plan(7, 'done'), plan(5, 'done')];
  assert.equal(latestDone(items).id, 7);
  assert.equal(latestDone([plan(3, 'cancelled')]), undefined);
  assert.equal(latestDone([]), undefined);
});

test('a plan label names id, planner, PoC (or the state), revision and time', () => {
  const today = new Date('2026-11-26T12:00:00.000Z');
  const done = planLabel(plan(7, 'done'), today);
  assert.match(done, /^#7 · darp · PoC 98\.1 % · rev 2 · \S/);
  assert.doesNotMatch(done, /Nov/, 'today: the time only');
  assert.match(planLabel(plan(7, 'done'), new Date('2026-12-03T12:00:00.000Z')), /rev 2 · .*\d/);
  assert.match(planLabel(plan(9, 'failed'), today), /^#9 · darp · failed · rev 2/);
  assert.match(planLabel(plan(4, 'queued', { planner: null, created: null }), today), /^#4 · queued · rev 2$/);
});

test('a structure scan is labelled by the wall it saw, not by its ground PoC', () => {
  const today = new Date('2026-11-26T12:00:00.000Z');
  const label = planLabel(plan(4, 'done', { planner: 'boustrophedon', metrics: { poc: 0, facade_poc: 0.97312, facade_3plus: 0.8 } }), today);
  assert.match(label, /^#4 · boustrophedon · wall 97\.3 % · rev 2/);
  assert.doesNotMatch(label, /PoC/);
});
