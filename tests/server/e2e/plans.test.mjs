// Plans: the job lifecycle with live events over WebSocket and SSE, the artifacts, cancellation in
// every stage (held there by the test hook UAVCOVER_TEST_HOLD_STAGE, docs/stops.md, so that nothing
// depends on how fast planning is), and a plan made through the API equals the CLI's plan for the same
// mission and seed.
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
  EventSocket,
  EventStream,
  freshDb,
  isTerminal,
  oliveGrove,
  postPlan,
  rectangle,
  runCli,
  startServer,
  tempDir,
  waitDone,
  waitJob,
} from './harness.mjs';

const PNG = Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]);

function assertJobMessage(msg, id) {
  assert.equal(msg.type, 'job', JSON.stringify(msg));
  assert.equal(msg.job.id, id);
  assert.ok(['queued', 'running', 'done', 'failed', 'cancelled'].includes(msg.job.state), msg.job.state);
  assert.equal(typeof msg.job.progress, 'number');
  assert.ok(msg.job.progress >= 0 && msg.job.progress <= 1, `progress ${msg.job.progress}`);
}

/** Running messages, then exactly one terminal message, the last. (Progress is not asserted to be
 * monotonic: the engine's stage fractions may step back, e.g. 0.67 -> 0.57 between stages.) */
function assertProgression(jobs) {
  const terminals = jobs.filter(isTerminal);
  assert.equal(terminals.length, 1, `one terminal message: ${jobs.map((x) => x.state)}`);
  assert.equal(jobs[jobs.length - 1], terminals[0], 'the terminal message is the last');
  assert.ok(jobs.some((j) => j.state === 'running'), `a running message: ${jobs.map((x) => x.state)}`);
}

eachBackend(describe, (backend) => {
  let server;
  before(async () => {
    server = await startServer({ db: freshDb(backend), args: ['--workers', '1'] });
    await enableSchemaChecks(server);
  });
  after(async () => {
    await server?.stop();
  });

  it('runs a plan job with progress over WebSocket and SSE, then serves its artifacts', async () => {
    const doc = oliveGrove();
    delete doc.camera;
    doc.altitude_m = 50;
    doc.spacing_m = 5; // a couple of seconds, so progress is seen while it runs
    const mission = await createMission(server, doc);

    const ws = await EventSocket.open(server);
    const post = await api(server, 'POST', `/api/v1/missions/${mission}/plans`, { body: { seed: 3 } });
    assert.equal(post.status, 202, post.text);
    const id = post.json.id;
    assert.equal(post.json.kind, 'plan');
    assert.equal(post.json.mission_id, mission);
    assert.equal(post.json.revision, 1);
    assert.ok(['queued', 'running'].includes(post.json.state), post.json.state);
    assert.equal(post.json.params.seed, 3);
    ws.send({ subscribe: { jobs: [id] } });
    const sse = await EventStream.open(server, [id]);
    assert.equal(sse.res.status, 200);
    assert.match(sse.res.headers.get('content-type'), /^text\/event-stream/);

    const running = await ws.waitFor((m) => m.type === 'job' && m.job.state === 'running' && m.job.progress > 0);
    assertJobMessage(running, id);
    assert.equal(typeof running.job.stage, 'string');
    const doneWs = await ws.waitFor((m) => m.type === 'job' && isTerminal(m.job));
    assertJobMessage(doneWs, id);
    assert.equal(doneWs.job.state, 'done', JSON.stringify(doneWs.job));
    assert.equal(doneWs.job.progress, 1);
    assert.ok(doneWs.job.result && typeof doneWs.job.result === 'object', 'the terminal message carries result');
    assert.equal(doneWs.job.error, null);

    const sseRunning = await sse.waitFor((r) => r.event === 'job' && r.data?.job?.state === 'running');
    assertJobMessage(sseRunning.data, id);
    const sseDone = await sse.waitFor((r) => r.event === 'job' && r.data && isTerminal(r.data.job));
    assert.equal(sseDone.data.job.state, 'done');
    assert.ok(sseDone.data.job.result && typeof sseDone.data.job.result === 'object');
    for (const r of sse.records) {
      assert.equal(r.event, 'job', r.raw);
      assertJobMessage(r.data, id);
    }
    // no more messages follow the terminal one (give the streams a moment)
    await new Promise((r) => setTimeout(r, 300));
    assertProgression(ws.messages.map((m) => m.job));
    assertProgression(sse.records.map((r) => r.data.job));
    ws.close();
    sse.close();

    const job = (await api(server, 'GET', `/api/v1/plans/${id}`)).json;
    assert.equal(job.state, 'done');
    assert.equal(job.attempts, 1);
    assert.ok(job.started && job.finished, 'started and finished times');
    for (const k of ['poc', 'flight_time_min', 'length_m', 'turns', 'compute_time_s']) {
      assert.equal(typeof job.metrics[k], 'number', `metrics.${k} in ${JSON.stringify(job.metrics)}`);
    }
    assert.ok(Array.isArray(job.warnings));
    const urls = job.artifacts.map((a) => a.url);
    for (const n of ['plan.json', 'paths.geojson', 'evaluation.json', 'images/plan.png', 'images/heatmap.png']) {
      assert.ok(urls.includes(`/api/v1/plans/${id}/${n}`), `artifact ${n} in ${urls}`);
    }
    // every listed artifact is served with its media type and size
    for (const a of job.artifacts) {
      if (a.url === null) continue; // e.g. the parts of a Litchi mission split in several files (zipped)
      const r = await api(server, 'GET', a.url);
      assert.equal(r.status, 200, `${a.url}: ${r.text.slice(0, 200)}`);
      assert.equal(r.headers.get('content-type').split(';')[0], a.media_type, a.url);
      assert.equal(r.bytes.length, a.size, a.url);
    }

    const plan = await api(server, 'GET', `/api/v1/plans/${id}/plan.json`);
    assert.equal(plan.status, 200);
    assert.ok(Array.isArray(plan.json?.uavs), 'plan.json has uavs');
    assert.equal(plan.json.seed, 3);
    const geo = await api(server, 'GET', `/api/v1/plans/${id}/paths.geojson`);
    assert.equal(geo.status, 200);
    assert.equal(JSON.parse(geo.text).type, 'FeatureCollection');
    const ev = await api(server, 'GET', `/api/v1/plans/${id}/evaluation.json`);
    assert.equal(ev.status, 200);
    assert.equal(typeof JSON.parse(ev.text), 'object');
    const png = await api(server, 'GET', `/api/v1/plans/${id}/images/plan.png`);
    assert.equal(png.status, 200);
    assert.equal(png.headers.get('content-type'), 'image/png');
    assert.deepEqual(png.bytes.subarray(0, 8), PNG);
    const svg = await api(server, 'GET', `/api/v1/plans/${id}/images/plan.svg`);
    assert.equal(svg.status, 200);
    assert.match(svg.text, /<svg/);

    const qgc = await api(server, 'GET', `/api/v1/plans/${id}/exports/qgc?uav=bravo`);
    assert.equal(qgc.status, 200, qgc.text);
    assert.match(qgc.headers.get('content-disposition'), /^attachment; *filename="?[^"/\\]+"?/);
    const qgcJson = JSON.parse(qgc.text);
    assert.equal(qgcJson.fileType, 'Plan');
    const kmz = await api(server, 'GET', `/api/v1/plans/${id}/exports/kmz?uav=bravo`);
    assert.equal(kmz.status, 200, kmz.text);
    assert.equal(kmz.bytes.subarray(0, 2).toString('latin1'), 'PK');
    assert.match(kmz.headers.get('content-disposition'), /filename=.*\.kmz/);
    const csv = await api(server, 'GET', `/api/v1/plans/${id}/exports/csv?uav=alpha`);
    assert.equal(csv.status, 200, csv.text);
    // several flying UAVs: the UAV must be named
    const noUav = await api(server, 'GET', `/api/v1/plans/${id}/exports/qgc`);
    const e = assertError(noUav, 422, 'uav');
    assert.match(e.message, /alpha/);
    // a UAV the plan does not have: no such export (404), naming the field
    assertError(await api(server, 'GET', `/api/v1/plans/${id}/exports/qgc?uav=zulu`), 404, 'uav');
    const nope = assertError(await api(server, 'GET', `/api/v1/plans/${id}/exports/nope?uav=alpha`), 404, 'format');
    // every route GET /api/v1/formats lists is served, and the unknown one's message lists exactly them
    const formats = await api(server, 'GET', '/api/v1/formats');
    assert.equal(formats.status, 200, formats.text);
    const routes = formats.json.routes.map((r) => r.name);
    assert.ok(routes.includes('kmz') && routes.includes('trajectory'), routes.join(' '));
    assert.ok(nope.message.endsWith(`expected one of ${routes.join(', ')}`), nope.message);
    for (const route of routes) {
      const r = await api(server, 'GET', `/api/v1/plans/${id}/exports/${route}?uav=bravo`);
      assert.equal(r.status, 200, `${route}: ${r.text.slice(0, 200)}`);
      assert.ok(r.bytes.length > 0, route);
    }
    assertError(await api(server, 'GET', `/api/v1/plans/${id}/images/nope.png`), 404);
  });

  it('answers malformed event messages and caps the subscriptions', async () => {
    const ws = await EventSocket.open(server);
    ws.send('{"subscribe": ');
    const e1 = await ws.waitFor((m) => m.type === 'error', 10000);
    assert.equal(typeof e1.error.field, 'string');
    assert.equal(typeof e1.error.message, 'string');
    ws.messages.length = 0;
    ws.send({ subscribe: { jobs: ['x'] } });
    await ws.waitFor((m) => m.type === 'error', 10000);
    ws.messages.length = 0;
    const many = Array.from({ length: 65 }, (_, i) => 1000000 + i);
    ws.send({ subscribe: { jobs: many } });
    const e3 = await ws.waitFor((m) => m.type === 'error', 10000);
    assert.match(e3.error.message, /64/);
    // the connection still works
    const mission = await createMission(server, rectangle());
    const job = await postPlan(server, mission, {});
    ws.send({ subscribe: { jobs: [job.id] } });
    const done = await ws.waitFor((m) => m.type === 'job' && m.job.id === job.id && isTerminal(m.job));
    assert.equal(done.job.state, 'done');
    ws.close();
  });

  it('makes the same plan as the CLI for the same mission and seed', async () => {
    const dir = tempDir();
    const doc = rectangle();
    const file = path.join(dir, 'mission.json');
    fs.writeFileSync(file, JSON.stringify(doc));
    const cli = runCli(['plan', file, '--out', path.join(dir, 'out'), '--seed', '7']);
    assert.equal(cli.code, 0, cli.stderr);
    const cliPlan = JSON.parse(fs.readFileSync(path.join(dir, 'out', 'plan.json'), 'utf8'));

    const mission = await createMission(server, doc);
    const job = await postPlan(server, mission, { seed: 7 });
    assert.equal((await waitDone(server, job.id)).state, 'done');
    const apiPlan = (await api(server, 'GET', `/api/v1/plans/${job.id}/plan.json`)).json;
    assert.ok(apiPlan?.totals, 'plan.json has totals');
    delete cliPlan.totals.compute_time_s;
    delete apiPlan.totals.compute_time_s;
    assert.deepEqual(apiPlan, cliPlan);
  });
});

// A server whose jobs of the missions named "hold <stage>" wait in that stage until they are cancelled
// (the test hook; at most 60 s, then they go on and would end done: the tests below would fail).
// a plan job makes no exports (they are made on request, docs/cache.md): its stages after the planner
const HELD_STAGES = ['evaluation', 'pictures', 'storing'];
const held = (stage) => ({ ...rectangle(), name: `hold ${stage}` });

eachBackend(describe, (backend) => {
  describe('cancellation in every stage', () => {
    let server;
    before(async () => {
      server = await startServer({
        db: freshDb(backend),
        args: ['--workers', '1'],
        env: { UAVCOVER_TEST_HOLD_STAGE: HELD_STAGES.map((s) => `${s}@hold ${s}`).join(',') },
      });
      await enableSchemaChecks(server);
    });
    after(async () => {
      await server?.stop();
    });

    async function assertCancelledWithoutArtifacts(id) {
      const job = await waitJob(server, id, isTerminal, { intervalMs: 20 });
      assert.equal(job.state, 'cancelled', JSON.stringify(job));
      assert.deepEqual(job.artifacts ?? [], [], 'a cancelled job has no artifacts');
      assertError(await api(server, 'GET', `/api/v1/plans/${id}/plan.json`), 409);
      return job;
    }

    it('cancels a queued job at once and a running job in whichever stage it is', async () => {
      const mission = await createMission(server, held('pictures'));
      const a = await postPlan(server, mission, { seed: 1 });
      // held in its pictures until the DELETE
      await waitJob(server, a.id, (j) => j.state === 'running' && j.stage === 'pictures', { intervalMs: 20 });
      // one worker: the second job waits
      const b = await postPlan(server, mission, { seed: 2 });
      const delB = await api(server, 'DELETE', `/api/v1/plans/${b.id}`);
      assert.equal(delB.status, 200, delB.text);
      assert.equal(delB.json.state, 'cancelled');
      assert.equal((await api(server, 'GET', `/api/v1/plans/${b.id}`)).json.state, 'cancelled');

      const del = await api(server, 'DELETE', `/api/v1/plans/${a.id}`);
      assert.equal(del.status, 200, del.text);
      assert.ok(
        del.json.state === 'cancelled' || (del.json.state === 'running' && del.json.cancel_requested === true),
        JSON.stringify(del.json),
      );
      await assertCancelledWithoutArtifacts(a.id);
      // a DELETE of the finished (cancelled) job deletes it
      const again = await api(server, 'DELETE', `/api/v1/plans/${a.id}`);
      assert.equal(again.status, 204, again.text);
      assertError(await api(server, 'GET', `/api/v1/plans/${a.id}`), 404, 'id');
      // the worker is free again: a job of another mission runs to its end
      const small = await createMission(server, rectangle());
      const c = await postPlan(server, small, {});
      assert.equal((await waitDone(server, c.id)).state, 'done');
    });

    for (const stage of HELD_STAGES) {
      it(`a DELETE during the stage ${stage} ends the job cancelled, never done`, async () => {
        const mission = await createMission(server, held(stage));
        const job = await postPlan(server, mission, {});
        await waitJob(server, job.id, (j) => j.state === 'running' && j.stage === stage, { intervalMs: 20 });
        assert.match(server.output.stderr, new RegExp(`test hold: ${stage}`));
        const del = await api(server, 'DELETE', `/api/v1/plans/${job.id}`);
        assert.equal(del.status, 200, del.text);
        await assertCancelledWithoutArtifacts(job.id);
      });
    }

    it('a time limit that runs out in a stage after the planner leaves it out and says so', async () => {
      const mission = await createMission(server, held('pictures'));
      const job = await postPlan(server, mission, { planner: 'boustrophedon', time_limit_s: 2 });
      const done = await waitJob(server, job.id, isTerminal, { intervalMs: 50 });
      assert.equal(done.state, 'done', JSON.stringify(done));
      const warnings = done.warnings ?? done.result.warnings;
      const warning = warnings.find((w) => w.startsWith('time limit reached after planning: left out '));
      assert.ok(warning, JSON.stringify(warnings));
      assert.match(warning, /pictures plan\.png, plan\.svg/);
      assert.doesNotMatch(warning, /exports/, 'a plan job makes no exports: none is left out');
      const names = done.artifacts.map((a) => a.name);
      assert.ok(names.includes('plan.json') && names.includes('paths.geojson'), names.join(' '));
      assert.ok(!names.some((n) => n.endsWith('.png') || n.startsWith('export/')), names.join(' '));
      // the exports are made from the stored plan on request, time limit or not
      const uav = done.result.uavs[0].id;
      const qgc = await api(server, 'GET', `/api/v1/plans/${job.id}/exports/qgc?uav=${uav}`);
      assert.equal(qgc.status, 200, qgc.text);
    });

    it('refuses before planning a mission whose UAVs cannot be separated under the ceiling', async () => {
      const doc = { ...rectangle(), name: 'twenty', uavs: 20 };
      const mission = await createMission(server, doc);
      const r = await api(server, 'POST', `/api/v1/missions/${mission}/plans`, { body: {} });
      assertError(r, 422, 'altitude.transition_ceiling_m');
      assert.match(r.json.error.message, /20 UAVs need transition altitudes/);
    });
  });
});
