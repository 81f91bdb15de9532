import { test } from 'node:test';
import assert from 'node:assert/strict';
import { apportion, equalShares, lockedFor, roundTo100, setShare, sharesFromDoc, toFractions } from '../../src/shares.ts';

const sum = (xs) => xs.reduce((a, b) => a + b, 0);

test('equal shares sum to 100 with the remainder on the first', () => {
  assert.deepEqual(equalShares(3), [34, 33, 33]);
  assert.deepEqual(equalShares(1), [100]);
  assert.deepEqual(equalShares(0), []);
  for (let n = 1; n <= 30; n++) assert.equal(sum(equalShares(n)), 100);
});

test('setShare rescales the others proportionally', () => {
  assert.deepEqual(setShare([50, 30, 20], 0, 60), [60, 24, 16]);
  assert.deepEqual(setShare([34, 33, 33], 0, 50), [50, 25, 25]);
  assert.deepEqual(setShare([50, 25, 25], 1, 30), [47, 30, 23]);
});

test('50/30/20 from equal shares, keeping the share set before', () => {
  let s = equalShares(3);
  const history = [];
  const set = (i, v) => {
    s = setShare(s, i, v, lockedFor(history, i, s.length));
    history.unshift(i);
  };
  set(0, 50);
  assert.deepEqual(s, [50, 25, 25]);
  set(1, 30);
  assert.deepEqual(s, [50, 30, 20]);
  set(2, 20);
  assert.deepEqual(s, [50, 30, 20]);
  set(2, 10);
  assert.deepEqual(s, [60, 30, 10]);
});

test('locked shares give way when the free ones cannot absorb the change', () => {
  assert.deepEqual(setShare([50, 30, 20], 1, 70, [0]), [21, 70, 9]);
  assert.deepEqual(setShare([50, 50], 0, 30, [1]), [30, 70]);
  assert.deepEqual(lockedFor([2, 1, 2, 0], 1, 4), [2, 0]);
  assert.deepEqual(lockedFor([0], 0, 3), []);
  assert.deepEqual(lockedFor([1, 0], 2, 2), []);
});

test('setShare with all others at 0 splits the rest equally', () => {
  assert.deepEqual(setShare([100, 0, 0], 0, 40), [40, 30, 30]);
  assert.deepEqual(setShare([100, 0, 0, 0], 0, 99), [97, 1, 1, 1], 'each of the others keeps 1 %');
});

test('no share reaches 0 (the server refuses it): 100 leaves 1 % to each other, 0 becomes 1 %', () => {
  assert.deepEqual(setShare([50, 30, 20], 1, 100), [1, 98, 1]);
  assert.deepEqual(setShare([50, 30, 20], 0, 0), [1, 59, 40]);
  // issue 29 defect 7: typing 0 into three shares in turn never gives a 0 share
  let s = [34, 33, 33];
  for (const i of [0, 1, 2]) {
    s = setShare(s, i, 0);
    assert.equal(sum(s), 100);
    assert.ok(s.every((x) => x >= 1), `${s}`);
  }
  assert.deepEqual(setShare([1, 1, 98], 2, 0), [50, 49, 1]);
});

test('one UAV always has 100', () => {
  assert.deepEqual(setShare([100], 0, 30), [100]);
  assert.deepEqual(setShare([7], 0, 100), [100]);
});

test('setShare clamps, rounds and ignores bad input', () => {
  assert.deepEqual(setShare([50, 50], 0, 150), [99, 1]);
  assert.deepEqual(setShare([50, 50], 0, -20), [1, 99]);
  assert.deepEqual(setShare([50, 50], 0, 33.6), [34, 66]);
  assert.deepEqual(setShare([50, 50], 0, Number.NaN), [50, 50]);
  assert.deepEqual(setShare([50, 50], 5, 10), [50, 50]);
  assert.deepEqual(setShare([], 0, 10), []);
});

test('rounding: displayed integers always sum to 100', () => {
  for (let n = 2; n <= 12; n++)
    for (let v = 0; v <= 100; v += 7) {
      const base = Array.from({ length: n }, (_, i) => (i * 37) % 11);
      const r = setShare(roundTo100(base), n - 1, v);
      assert.equal(sum(r), 100, `n=${n} v=${v}`);
      assert.equal(r[n - 1], Math.min(100 - (n - 1), Math.max(1, v)), 'clamped to [1, 100 - (n - 1)]');
      assert.ok(r.every((x) => Number.isInteger(x) && x >= 1));
    }
});

test('roundTo100 uses the largest remainder', () => {
  assert.deepEqual(roundTo100([1, 1, 1]), [34, 33, 33]);
  assert.deepEqual(roundTo100([0.15, 0.4, 0.45]), [15, 40, 45]);
  assert.deepEqual(roundTo100([2, 1]), [67, 33]);
  assert.deepEqual(roundTo100([0, 0]), [50, 50]);
  assert.deepEqual(roundTo100([1e308, 1e308]), [50, 50]);
  assert.deepEqual(roundTo100([Number.NaN, 1]), [0, 100]);
  assert.equal(sum(apportion([1, 2, 3, 4], 7)), 7);
});

test('shares from the document follow the library rule for absent ones', () => {
  assert.deepEqual(sharesFromDoc([0.6, 0.4]), [60, 40]);
  assert.deepEqual(sharesFromDoc([3, 2]), [60, 40]);
  assert.deepEqual(sharesFromDoc([0.5, undefined, undefined]), [50, 25, 25]);
  assert.deepEqual(sharesFromDoc([undefined, undefined, undefined]), [34, 33, 33]);
  assert.deepEqual(toFractions([50, 30, 20]), [0.5, 0.3, 0.2]);
});
