// The OpenAPI document at /api/v1/openapi.json: valid for an independent validator
// (@apidevtools/swagger-parser), and the server's answers match its response schemas (ajv).
import { describe, it, before, after } from 'node:test';
import assert from 'node:assert/strict';
import {
  api,
  Contract,
  createMission,
  eachBackend,
  freshDb,
  postPlan,
  rectangle,
  startServer,
  waitDone,
  waitJob,
  slowMission,
} from './harness.mjs';

eachBackend(describe, (backend) => {
  let server;
  let contract;
  before(async () => {
    server = await startServer({ db: freshDb(backend), args: ['--workers', '1', '--max-queued', '1'] });
  });
  after(async () => {
    await server?.stop();
  });

  it('serves a valid OpenAPI 3 document', async () => {
    const r = await api(server, 'GET', '/api/v1/openapi.json', { check: false });
    assert.equal(r.status, 200);
    assert.match(r.headers.get('content-type'), /application\/(vnd\.oai\.openapi\+)?json/);
    assert.match(r.json.openapi, /^3\./);
    contract = await Contract.load(server); // SwaggerParser.validate() throws on an invalid document
    server._contract = contract;
    // the documented paths cover the API guide's routes
    const paths = Object.keys(contract.deref.paths);
    for (const p of [
      '/api/v1/missions',
      '/api/v1/missions/{id}',
      '/api/v1/missions/{id}/revisions/{n}',
      '/api/v1/missions/{id}/plans',
      '/api/v1/plans/{id}',
      '/api/v1/plans/{id}/plan.json',
      '/api/v1/uavs',
      '/api/v1/cameras',
    ]) {
      assert.ok(contract.template(p.replace(/\{[^}]+\}/g, '1')), `${p} documented (paths: ${paths.join(' ')})`);
    }
  });

  it('answers as its schemas say', async () => {
    assert.ok(contract, 'the document loaded');
    const strict = (method, p, r) => contract.check(method, p, r.status, r.json, { strict: true });
    const call = async (method, p, opts = {}) => {
      const r = await api(server, method, p, { ...opts, check: false });
      assert.notEqual(r.json, undefined, `${method} ${p}: JSON answer, got ${r.status} ${r.text.slice(0, 200)}`);
      strict(method, p, r);
      return r;
    };
    // missions
    const post = await call('POST', '/api/v1/missions', { body: rectangle() });
    assert.equal(post.status, 201);
    const id = post.json.id;
    await call('GET', `/api/v1/missions/${id}`);
    await call('GET', '/api/v1/missions?limit=1');
    await call('GET', '/api/v1/missions?name=rect&bbox=9,45,10,46');
    const put = await call('PUT', `/api/v1/missions/${id}`, { body: { ...rectangle(), name: 'renamed' } });
    assert.equal(put.status, 200);
    await call('GET', `/api/v1/missions/${id}/revisions/1`);
    // errors
    assert.equal((await call('POST', '/api/v1/missions', { body: '{' })).status, 400);
    assert.equal((await call('GET', '/api/v1/missions/abc')).status, 400);
    assert.equal((await call('GET', '/api/v1/missions?limit=x')).status, 400);
    assert.equal((await call('GET', '/api/v1/missions/999999')).status, 404);
    assert.equal((await call('POST', '/api/v1/missions', { body: { name: 'no area' } })).status, 422);
    assert.equal(
      (await call('POST', '/api/v1/missions', { body: '{}', headers: { 'content-type': 'text/plain' } })).status,
      415,
    );
    // jobs
    const job = await call('POST', `/api/v1/missions/${id}/plans`, { body: { seed: 7 } });
    assert.equal(job.status, 202);
    await waitDone(server, job.json.id);
    const done = await call('GET', `/api/v1/plans/${job.json.id}`);
    assert.equal(done.json.state, 'done');
    await call('GET', `/api/v1/plans/${job.json.id}/plan.json`);
    await call('GET', `/api/v1/plans/${job.json.id}/evaluation.json`);
    // an artifact that is not JSON: the operation and status are documented
    const png = await api(server, 'GET', `/api/v1/plans/${job.json.id}/images/plan.png`, { check: false });
    assert.equal(png.status, 200);
    const t = contract.template(`/api/v1/plans/${job.json.id}/images/plan.png`);
    assert.ok(contract.deref.paths[t]?.get?.responses?.['200'], `GET ${t} 200 documented`);
    // 409 and 503 with a slow job running and one queued (--workers 1 --max-queued 1)
    const slow = (await call('POST', '/api/v1/missions', { body: slowMission(2) })).json.id;
    const a = (await call('POST', `/api/v1/missions/${slow}/plans`, { body: {} })).json.id;
    await waitJob(server, a, (j) => j.state === 'running', { intervalMs: 20 });
    assert.equal((await call('DELETE', `/api/v1/missions/${slow}`)).status, 409);
    assert.equal((await call('GET', `/api/v1/plans/${a}/plan.json`)).status, 409);
    const b = (await call('POST', `/api/v1/missions/${slow}/plans`, { body: {} })).json.id;
    assert.equal((await call('POST', `/api/v1/missions/${slow}/plans`, { body: {} })).status, 503);
    assert.equal((await call('DELETE', `/api/v1/plans/${b}`)).status, 200);
    assert.equal((await call('DELETE', `/api/v1/plans/${a}`)).status, 200);
    await waitDone(server, a);
    assert.equal((await call('GET', `/api/v1/plans/${a}`)).json.state, 'cancelled');
    // catalogs
    const uavs = await call('GET', '/api/v1/uavs');
    assert.ok(uavs.json.items.length > 0, 'seeded UAV catalog');
    const cams = await call('GET', '/api/v1/cameras');
    assert.ok(cams.json.items.length > 0, 'seeded camera catalog');
    const cam = await call('POST', '/api/v1/cameras', {
      body: { name: 'e2e cam', sensor_width_mm: 13.2, focal_length_mm: 8.8, image_width_px: 5472, hfov_deg: 73.7 },
    });
    assert.equal(cam.status, 201, cam.text);
    await call('GET', `/api/v1/cameras/${cam.json.id}`);
    const uav = await call('POST', '/api/v1/uavs', {
      body: { name: 'e2e uav', speed_mps: 8, max_accel_mps2: 2, endurance_min: 25, cost_per_min_eur: 1.5, camera_id: cam.json.id },
    });
    assert.equal(uav.status, 201, uav.text);
    await call('GET', `/api/v1/uavs/${uav.json.id}`);
    assert.equal((await call('POST', '/api/v1/uavs', { body: { name: 'bad', speed_mps: -1 } })).status, 422);
    // operations
    await call('GET', '/api/v1/planners');
    await call('GET', '/api/v1/formats');
    // the mission goes last (its jobs are finished)
    const del = await api(server, 'DELETE', `/api/v1/missions/${id}`, { check: false });
    assert.equal(del.status, 204);
    const t2 = contract.template(`/api/v1/missions/${id}`);
    assert.ok(contract.deref.paths[t2]?.delete?.responses?.['204'], 'DELETE 204 documented');
    assert.ok(contract.checked.length >= 30, `checked ${contract.checked.length} answers`);
  });
});
