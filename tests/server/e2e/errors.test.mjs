// Every error code of the API, each as {"error": {"field", "message"}} without paths or stack traces:
// 400, 404, 405, 409, 413, 415, 422 (the CLI's field-named message) and 503 with Retry-After.
import { describe, it, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import {
  api,
  assertError,
  createMission,
  eachBackend,
  enableSchemaChecks,
  freshDb,
  oliveGrove,
  postPlan,
  rawRequest,
  rectangle,
  runCli,
  slowMission,
  startServer,
  tempDir,
  waitDone,
  waitJob,
} from './harness.mjs';

eachBackend(describe, (backend) => {
  let server;
  let mission;
  before(async () => {
    server = await startServer({ db: freshDb(backend), args: ['--workers', '1', '--max-queued', '1'] });
    await enableSchemaChecks(server);
    mission = await createMission(server, rectangle());
  });
  after(async () => {
    await server?.stop();
  });

  it('400: malformed JSON, bad ids and bad query parameters', async () => {
    assertError(await api(server, 'POST', '/api/v1/missions', { body: '{"name": ' }), 400, 'body');
    assertError(await api(server, 'POST', '/api/v1/missions', { body: '{"a": 1,}' }), 400, 'body');
    assertError(await api(server, 'PUT', `/api/v1/missions/${mission}`, { body: '[1, 2' }), 400, 'body');
    assertError(await api(server, 'POST', `/api/v1/missions/${mission}/plans`, { body: 'seed=7' }), 400, 'body');
    for (const bad of ['abc', '0', '-1', '1.5', '1e3', '99999999999999999999999', '%20']) {
      assertError(await api(server, 'GET', `/api/v1/missions/${bad}`), 400, 'id');
    }
    assertError(await api(server, 'GET', '/api/v1/plans/x1'), 400, 'id');
    assertError(await api(server, 'DELETE', '/api/v1/plans/0'), 400, 'id');
    assertError(await api(server, 'GET', `/api/v1/missions/${mission}/revisions/zero`), 400);
    assertError(await api(server, 'GET', '/api/v1/missions?limit=abc'), 400, 'limit');
    assertError(await api(server, 'GET', '/api/v1/missions?limit=0'), 400, 'limit');
    assertError(await api(server, 'GET', '/api/v1/missions?limit=100000'), 400, 'limit');
    assertError(await api(server, 'GET', '/api/v1/missions?cursor=next'), 400, 'cursor');
    assertError(await api(server, 'GET', '/api/v1/missions?bbox=1,2,3'), 400, 'bbox');
    assertError(await api(server, 'GET', '/api/v1/missions?bbox=a,b,c,d'), 400, 'bbox');
  });

  it('404: unknown routes and ids', async () => {
    assertError(await api(server, 'GET', '/api/v1/nothing-here'), 404);
    assertError(await api(server, 'GET', '/api/v2/missions'), 404);
    assertError(await api(server, 'GET', '/api/v1/missions/1/nothing'), 404);
    assertError(await api(server, 'GET', '/api/v1/missions/999999'), 404);
    assertError(await api(server, 'PUT', '/api/v1/missions/999999', { body: rectangle() }), 404);
    assertError(await api(server, 'DELETE', '/api/v1/missions/999999'), 404);
    assertError(await api(server, 'GET', `/api/v1/missions/${mission}/revisions/99`), 404);
    assertError(await api(server, 'POST', '/api/v1/missions/999999/plans', { body: {} }), 404);
    assertError(await api(server, 'GET', '/api/v1/plans/999999'), 404);
    assertError(await api(server, 'DELETE', '/api/v1/plans/999999'), 404);
    assertError(await api(server, 'GET', '/api/v1/plans/999999/plan.json'), 404);
    assertError(await api(server, 'GET', '/api/v1/uavs/999999'), 404);
    // a path with dots does not reach the disk
    const dots = await rawRequest(server, 'GET', '/api/v1/../../etc/passwd');
    assert.ok([400, 404].includes(dots.status), `${dots.status}`);
    assert.doesNotMatch(dots.text, /root:/);
  });

  it('405: wrong method, with Allow', async () => {
    const r = await api(server, 'DELETE', '/api/v1/missions');
    assertError(r, 405);
    const allow = (r.headers.get('allow') || '').split(/,\s*/);
    assert.ok(allow.includes('GET') && allow.includes('POST'), `Allow: ${allow}`);
    const r2 = await api(server, 'PATCH', `/api/v1/missions/${mission}`, { body: {} });
    assertError(r2, 405);
    const allow2 = (r2.headers.get('allow') || '').split(/,\s*/);
    for (const m of ['GET', 'PUT', 'DELETE']) assert.ok(allow2.includes(m), `Allow: ${allow2}`);
    assertError(await api(server, 'PUT', '/api/v1/plans/1'), 405);
    assertError(await api(server, 'POST', '/api/v1/openapi.json', { body: {} }), 405);
  });

  it('415: a body that is not JSON', async () => {
    const r = await api(server, 'POST', '/api/v1/missions', {
      body: JSON.stringify(rectangle()),
      headers: { 'content-type': 'text/plain' },
    });
    assertError(r, 415);
    const r2 = await api(server, 'PUT', `/api/v1/missions/${mission}`, {
      body: JSON.stringify(rectangle()),
      headers: { 'content-type': 'application/x-www-form-urlencoded' },
    });
    assertError(r2, 415);
  });

  it('413: a body over the limit (default 10 MB)', async () => {
    const doc = rectangle();
    doc.name = 'x'.repeat(11 * 1024 * 1024);
    const body = JSON.stringify(doc);
    // a client that announces the body and waits for 100 Continue gets the 413 before sending it
    const r = await rawRequest(server, 'POST', '/api/v1/missions', {
      headers: { 'content-type': 'application/json' },
      body,
      expectContinue: true,
    });
    assert.equal(r.status, 413, r.text.slice(0, 300));
    assertError(r, 413);
    // a client that sends it all at once: 413, or the connection closed under it (the server need not
    // read 11 MB it refuses); nothing is stored either way
    const before = (await api(server, 'GET', '/api/v1/missions?limit=1000')).json.items.length;
    try {
      const blunt = await rawRequest(server, 'POST', '/api/v1/missions', {
        headers: { 'content-type': 'application/json' },
        body,
      });
      assertError(blunt, 413);
    } catch (e) {
      assert.ok(['EPIPE', 'ECONNRESET'].includes(e.code), `${e.code}: ${e.message}`);
    }
    // the server still serves, and stored nothing
    assert.equal((await api(server, 'GET', '/healthz')).status, 200);
    assert.equal((await api(server, 'GET', '/api/v1/missions?limit=1000')).json.items.length, before);
  });

  it('422: an invalid mission names the field, with the same message as the CLI', async () => {
    const cases = [
      (d) => {
        d.uavs[1].speed_mps = -1;
      },
      (d) => {
        d.spacing_m = 5; // next to the camera
      },
      (d) => {
        d.area.coordinates = [[[22.9, 40.6]]];
      },
      (d) => {
        d.uavs = [];
      },
      (d) => {
        d.planner = 'no-such-planner';
      },
    ];
    const dir = tempDir();
    for (const [i, mutate] of cases.entries()) {
      const doc = oliveGrove();
      mutate(doc);
      const r = await api(server, 'POST', '/api/v1/missions', { body: doc });
      const err = assertError(r, 422);
      assert.ok(err.field.length > 0, `field named: ${r.text}`);
      const file = path.join(dir, `bad${i}.json`);
      fs.writeFileSync(file, JSON.stringify(doc));
      const cli = runCli(['plan', file, '--out', path.join(dir, `out${i}`)]);
      assert.equal(cli.code, 2, cli.stderr);
      assert.ok(cli.stderr.includes(err.field), `CLI stderr ${JSON.stringify(cli.stderr)} names ${err.field}`);
      assert.ok(cli.stderr.includes(err.message), `CLI stderr ${JSON.stringify(cli.stderr)} has ${JSON.stringify(err.message)}`);
    }
    // a body that is JSON but no mission
    assertError(await api(server, 'POST', '/api/v1/missions', { body: '[1, 2, 3]' }), 422);
    assertError(await api(server, 'POST', '/api/v1/missions', { body: '42' }), 422);
    // invalid job parameters
    assertError(await api(server, 'POST', `/api/v1/missions/${mission}/plans`, { body: { planner: 'nope' } }), 422, 'planner');
    assertError(await api(server, 'POST', `/api/v1/missions/${mission}/plans`, { body: { seed: 'seven' } }), 422, 'seed');
    assertError(await api(server, 'POST', `/api/v1/missions/${mission}/plans`, { body: { time_limit_s: -3 } }), 422, 'time_limit_s');
  });

  it('409 for a busy mission and an unfinished job, 503 with Retry-After when the queue is full', async () => {
    const slow = await createMission(server, slowMission(2));
    const a = await postPlan(server, slow, { seed: 1 });
    await waitJob(server, a.id, (j) => j.state === 'running', { intervalMs: 20 });
    assertError(await api(server, 'DELETE', `/api/v1/missions/${slow}`), 409);
    assertError(await api(server, 'GET', `/api/v1/plans/${a.id}/plan.json`), 409);
    assertError(await api(server, 'GET', `/api/v1/plans/${a.id}/exports/qgc?uav=alpha`), 409);

    // --workers 1 --max-queued 1: one job waits, the next is refused
    const b = await postPlan(server, slow, { seed: 2 });
    assert.equal(b.state, 'queued');
    assertError(await api(server, 'GET', `/api/v1/plans/${b.id}/plan.json`), 409);
    const refused = [];
    for (let i = 0; i < 3; i++) refused.push(await api(server, 'POST', `/api/v1/missions/${mission}/plans`, { body: {} }));
    for (const r of refused) {
      assertError(r, 503);
      const retry = r.headers.get('retry-after');
      assert.match(retry || '', /^\d+$/, `Retry-After: ${retry}`);
      assert.ok(Number(retry) >= 1);
    }
    // with one queued job (not running) the mission cannot go either
    assertError(await api(server, 'DELETE', `/api/v1/missions/${slow}`), 409);

    assert.equal((await api(server, 'DELETE', `/api/v1/plans/${b.id}`)).json.state, 'cancelled');
    assert.equal((await api(server, 'DELETE', `/api/v1/plans/${a.id}`)).status, 200);
    assert.equal((await waitDone(server, a.id)).state, 'cancelled');
    // room again
    const c = await postPlan(server, mission, {});
    assert.equal((await waitDone(server, c.id)).state, 'done');
    assert.equal((await api(server, 'DELETE', `/api/v1/missions/${slow}`)).status, 204);
  });

  describe('with --max-body 1024', () => {
    let small;
    before(async () => {
      small = await startServer({ db: freshDb(backend), args: ['--max-body', '1024'] });
    });
    after(async () => {
      await small?.stop();
    });
    it('413 for 2000 bytes, fine for less than 1024', async () => {
      const doc = rectangle();
      doc.name = 'y'.repeat(2000);
      const r = await rawRequest(small, 'POST', '/api/v1/missions', {
        headers: { 'content-type': 'application/json' },
        body: JSON.stringify(doc),
      });
      assert.equal(r.status, 413, r.text);
      assertError(r, 413);
      const tiny = {
        name: 'tiny',
        area: { type: 'Polygon', coordinates: [[[9.15, 45.39], [9.151, 45.39], [9.151, 45.391], [9.15, 45.391], [9.15, 45.39]]] },
        spacing_m: 10,
        altitude_m: 30,
        uavs: [{ id: 'a', speed_mps: 3, endurance_min: 20 }],
      };
      assert.ok(JSON.stringify(tiny).length < 1024);
      const ok = await api(small, 'POST', '/api/v1/missions', { body: tiny });
      assert.equal(ok.status, 201, ok.text);
    });
  });
});
