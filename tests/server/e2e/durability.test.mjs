// Durability: kill -9 during a burst of writes loses no acknowledged mission; a job running when the
// server dies runs again after the restart (and fails after 3 interrupted attempts), on both databases.
import { describe, it } from 'node:test';
import assert from 'node:assert/strict';
import {
  api,
  createMission,
  eachBackend,
  freshDb,
  leaseArgs,
  postPlan,
  rectangle,
  slowMission,
  sleep,
  startServer,
  waitDone,
  waitJob,
} from './harness.mjs';

eachBackend(describe, (backend) => {
  it('kill -9 during a burst of concurrent POSTs: every acknowledged mission is there after a restart', async (t) => {
    const db = freshDb(backend);
    let server = await startServer({ db, seed: false });
    const acked = [];
    let stop = false;
    let failures = 0;
    const loop = async (n) => {
      for (let i = 0; !stop; i++) {
        const doc = rectangle();
        doc.name = `burst ${n}-${i}`;
        try {
          const r = await api(server, 'POST', '/api/v1/missions', { body: doc, check: false });
          if (r.status === 201) acked.push({ id: r.json.id, name: doc.name });
          else if (!stop) assert.fail(`POST answered ${r.status}: ${r.text}`);
        } catch (e) {
          if (e.code === 'ERR_ASSERTION') throw e;
          failures++; // the connection died with the server
          return;
        }
      }
    };
    const loops = Array.from({ length: 8 }, (_, n) => loop(n));
    // let the burst run, then crash the server in the middle of it
    const t0 = Date.now();
    while (acked.length < 150 && Date.now() - t0 < 10000) await sleep(20);
    const before = acked.length;
    await server.kill();
    stop = true;
    await Promise.all(loops);
    assert.ok(before >= 20, `only ${before} missions acknowledged before the kill`);
    assert.ok(failures > 0 || acked.length > 0);
    t.diagnostic(`${acked.length} missions acknowledged, ${failures} requests cut by the kill`);

    server = await startServer({ db, seed: false });
    try {
      assert.equal((await api(server, 'GET', '/readyz')).status, 200);
      for (const { id, name } of acked) {
        const r = await api(server, 'GET', `/api/v1/missions/${id}`);
        assert.equal(r.status, 200, `mission ${id} (${name}) acknowledged but lost: ${r.text}`);
        assert.equal(r.json.name, name);
      }
      // every stored mission is whole, and the ids are unique
      const list = await api(server, 'GET', '/api/v1/missions?limit=1000');
      assert.ok(list.json.items.length >= acked.length);
      assert.equal(new Set(acked.map((a) => a.id)).size, acked.length);
      for (const m of list.json.items) {
        const r = await api(server, 'GET', `/api/v1/missions/${m.id}`);
        assert.equal(r.status, 200);
        assert.equal(r.json.mission.uavs.length, 3);
      }
      // and it takes new writes
      await createMission(server, rectangle());
    } finally {
      await server.stop();
    }
  });
});

eachBackend(describe, (backend) => {
  // SQLite: the restarted server queues its running jobs again at once; PostgreSQL (shared by servers):
  // the job is leased again when the dead server's lease expires (short leases here)
  const args = ['--workers', '1', ...leaseArgs(1500)];

  it('a job running at kill -9 runs again after the restart and ends done (attempts >= 2)', async () => {
    const db = freshDb(backend);
    let server = await startServer({ db, seed: false, args });
    const mission = await createMission(server, slowMission(4));
    const job = await postPlan(server, mission, { seed: 5 });
    await waitJob(server, job.id, (j) => j.state === 'running', { intervalMs: 20 });
    await sleep(300);
    await server.kill();

    server = await startServer({ db, seed: false, args });
    try {
      const seen = (await api(server, 'GET', `/api/v1/plans/${job.id}`)).json;
      assert.ok(['queued', 'running'].includes(seen.state), `after the restart: ${seen.state}`);
      const done = await waitDone(server, job.id, { timeoutMs: 120000 });
      assert.equal(done.state, 'done', JSON.stringify(done));
      assert.ok(done.attempts >= 2, `attempts ${done.attempts}`);
      assert.equal((await api(server, 'GET', `/api/v1/plans/${job.id}/plan.json`)).status, 200);
    } finally {
      await server.stop();
    }
  });

  it('a job interrupted 3 times fails, and says so', async () => {
    const db = freshDb(backend);
    let server = await startServer({ db, seed: false, args });
    const mission = await createMission(server, slowMission(2));
    const job = await postPlan(server, mission, {});
    for (let attempt = 1; attempt <= 3; attempt++) {
      await waitJob(server, job.id, (j) => j.state === 'running' && j.attempts === attempt, { intervalMs: 20 });
      await server.kill();
      server = await startServer({ db, seed: false, args });
    }
    try {
      const j = await waitDone(server, job.id, { timeoutMs: 60000 });
      assert.equal(j.state, 'failed', JSON.stringify(j));
      assert.equal(j.attempts, 3);
      assert.ok(j.error && typeof j.error.message === 'string', JSON.stringify(j.error));
      assert.match(j.error.message, /interrupt/i);
    } finally {
      await server.stop();
    }
  });
});
