import { test } from 'node:test';
import assert from 'node:assert/strict';
import { defaultParams, displayValue, fieldsFromSchema, paramsForSchema, parseField } from '../../src/schema-form.ts';

// the shapes GET /api/v1/planners gives
const darp = {
  name: 'darp',
  params: [
    { default: 4000, description: 'DARP iterations per attempt', maximum: 1000000.0, minimum: 1.0, name: 'max_iterations', type: 'integer' },
    { default: true, description: 'search the grid', name: 'optimise_placement', type: 'boolean' },
  ],
};
const bous = {
  name: 'boustrophedon',
  params: [{ default: null, description: 'Direction', maximum: 360.0, minimum: -360.0, name: 'angle_deg', type: 'number' }],
};

test('fields carry kind, bounds and defaults from the schema', () => {
  const f = fieldsFromSchema(darp);
  assert.equal(f.length, 2);
  assert.deepEqual(
    { name: f[0].name, kind: f[0].kind, min: f[0].min, max: f[0].max, def: f[0].default, label: f[0].label },
    { name: 'max_iterations', kind: 'integer', min: 1, max: 1000000, def: 4000, label: 'max iterations' },
  );
  assert.equal(f[1].kind, 'boolean');
  assert.equal(fieldsFromSchema(bous)[0].default, null);
  assert.deepEqual(fieldsFromSchema(null), []);
  assert.deepEqual(fieldsFromSchema({ name: 'x' }), []);
});

test('enum and string fields, and JSON-Schema properties', () => {
  const f = fieldsFromSchema({
    properties: { pattern: { type: 'string', enum: ['a', 'b'], default: 'a' }, label: { type: 'string' }, odd: { type: 'object' } },
  });
  assert.deepEqual(
    f.map((x) => [x.name, x.kind]),
    [
      ['pattern', 'enum'],
      ['label', 'string'],
      ['odd', 'string'],
    ],
  );
  assert.deepEqual(parseField(f[0], 'b'), { value: 'b' });
  assert.ok(parseField(f[0], 'c').error);
  assert.deepEqual(parseField(f[1], ' hi '), { value: 'hi' });
});

test('integers: whole numbers within the bounds', () => {
  const [it] = fieldsFromSchema(darp);
  assert.deepEqual(parseField(it, '250'), { value: 250 });
  assert.deepEqual(parseField(it, ''), { value: undefined });
  assert.equal(parseField(it, '1.5').error, 'must be a whole number');
  assert.equal(parseField(it, '0').error, 'must be at least 1');
  assert.equal(parseField(it, '2000000').error, 'must be at most 1000000');
  assert.equal(parseField(it, 'abc').error, 'must be a number');
  assert.equal(parseField(it, 'abc').value, undefined);
});

test('numbers accept fractions and negatives within the bounds', () => {
  const [a] = fieldsFromSchema(bous);
  assert.deepEqual(parseField(a, '-12.5'), { value: -12.5 });
  assert.equal(parseField(a, '400').error, 'must be at most 360');
  assert.deepEqual(parseField(a, '  '), { value: undefined });
});

test('booleans from check boxes and text', () => {
  const b = fieldsFromSchema(darp)[1];
  assert.deepEqual(parseField(b, false), { value: false });
  assert.deepEqual(parseField(b, 'true'), { value: true });
  assert.ok(parseField(b, 'yes').error);
});

test('defaults and the parameters kept in the document', () => {
  const f = fieldsFromSchema(darp);
  assert.deepEqual(defaultParams(f), { max_iterations: 4000, optimise_placement: true });
  assert.deepEqual(defaultParams(fieldsFromSchema(bous)), {});
  // defaults and unknown names are left out (the server fills defaults in; unknown names are refused)
  assert.deepEqual(paramsForSchema(f, { max_iterations: 4000, optimise_placement: false, angle_deg: 3 }), { optimise_placement: false });
  assert.equal(displayValue(null), '');
  assert.equal(displayValue(4000), '4000');
});
