// Scale-out: two servers on one PostgreSQL database share the job queue. 40 jobs end done, each
// exactly once (the jobs table's `completions`), and again when one server is killed mid-job: its
// jobs are leased again when their leases expire.
import { describe, it, after } from 'node:test';
import assert from 'node:assert/strict';
import {
  api,
  backends,
  createMission,
  EventSocket,
  freshDb,
  leaseArgs,
  psql,
  rectangle,
  sleep,
  startServer,
} from './harness.mjs';

const JOBS = 40;

async function queueJobs(servers, mission) {
  const ids = [];
  for (let i = 0; i < JOBS; i++) {
    const s = servers[i % servers.length];
    const r = await api(s, 'POST', `/api/v1/missions/${mission}/plans`, { body: { seed: i + 1 } });
    assert.equal(r.status, 202, r.text);
    ids.push(r.json.id);
  }
  return ids;
}

/** Waits until no job is queued or running; returns the lease holders seen on running jobs meanwhile. */
async function waitAllTerminal(db, timeoutMs) {
  const t0 = Date.now();
  const workers = new Set();
  for (;;) {
    const rows = psql(db.url, "SELECT state, worker FROM jobs WHERE state IN ('queued', 'running')");
    for (const [state, worker] of rows) if (state === 'running' && worker) workers.add(worker);
    if (rows.length === 0) return workers;
    if (Date.now() - t0 > timeoutMs) {
      const all = psql(db.url, 'SELECT id, state, attempts, worker FROM jobs ORDER BY id');
      throw new Error(`jobs still open after ${timeoutMs} ms: ${JSON.stringify(all)}`);
    }
    await sleep(50);
  }
}

function jobRows(db) {
  return psql(db.url, 'SELECT id, state, attempts, completions, worker FROM jobs ORDER BY id').map(
    ([id, state, attempts, completions, worker]) => ({
      id: Number(id),
      state,
      attempts: Number(attempts),
      completions: Number(completions),
      worker,
    }),
  );
}

describe('postgresql', { skip: !backends().includes('postgresql') && 'UAVCOVER_TEST_PG_URL_FILE is not set' }, () => {
  const running = new Set();
  after(async () => {
    for (const s of running) await s.stop();
  });
  const start = async (db, extra = []) => {
    const s = await startServer({ db, args: ['--workers', '2', ...extra] });
    running.add(s);
    return s;
  };

  it('two servers share the queue: 40 jobs done, each exactly once', async (t) => {
    const db = freshDb('postgresql');
    const a = await start(db);
    const b = await start(db);
    const mission = await createMission(a, rectangle());
    // a client of server A sees every job, those server B runs included (events come from the database)
    const ws = await EventSocket.open(a);
    const ids = await queueJobs([a, b], mission);
    ws.send({ subscribe: { jobs: ids } });
    const workers = await waitAllTerminal(db, 150000);
    for (const id of ids) {
      const m = await ws.waitFor((x) => x.type === 'job' && x.job.id === id && x.job.state === 'done', 20000);
      assert.equal(m.job.progress, 1);
    }
    ws.close();
    const rows = jobRows(db);
    assert.deepEqual(
      rows.map((r) => r.id),
      ids,
    );
    for (const r of rows) {
      assert.equal(r.state, 'done', JSON.stringify(r));
      assert.equal(r.completions, 1, JSON.stringify(r));
      assert.equal(r.attempts, 1, JSON.stringify(r));
    }
    // both servers planned (the worker names, seen on running jobs, are host-PID-random)
    const seen = [...workers];
    const byA = seen.filter((w) => w.includes(`-${a.pid}-`)).length;
    const byB = seen.filter((w) => w.includes(`-${b.pid}-`)).length;
    t.diagnostic(`lease holders seen: ${seen.join(', ')}`);
    assert.ok(byA > 0 && byB > 0, `both servers ran jobs: ${seen}`);
    // the other server reports the jobs the same way
    for (const id of ids.slice(0, 5)) {
      const j = (await api(b, 'GET', `/api/v1/plans/${id}`)).json;
      assert.equal(j.state, 'done');
      assert.equal((await api(a, 'GET', `/api/v1/plans/${id}/plan.json`)).status, 200);
    }
    await a.stop();
    await b.stop();
    running.delete(a);
    running.delete(b);
  });

  it('one server killed mid-job: its jobs are leased again, all 40 done exactly once', async (t) => {
    const db = freshDb('postgresql');
    const lease = leaseArgs(1500);
    const a = await start(db, lease);
    const b = await start(db, lease);
    const mission = await createMission(a, rectangle());
    const ids = await queueJobs([a, b], mission);
    // kill B while it holds a running job
    const t0 = Date.now();
    for (;;) {
      const held = psql(db.url, `SELECT id FROM jobs WHERE state = 'running' AND worker LIKE '%-${b.pid}-%'`);
      if (held.length > 0) break;
      assert.ok(Date.now() - t0 < 60000, 'server B never ran a job');
      await sleep(10);
    }
    await b.kill();
    running.delete(b);
    const orphaned = psql(db.url, `SELECT id FROM jobs WHERE state = 'running' AND worker LIKE '%-${b.pid}-%'`).map(
      ([id]) => Number(id),
    );
    assert.ok(orphaned.length > 0, 'B died holding a job');
    t.diagnostic(`server B killed holding jobs ${orphaned.join(', ')}${lease.length ? ' (--lease-ms 1500)' : ' (default lease)'}`);
    await waitAllTerminal(db, 150000);
    const rows = jobRows(db);
    assert.deepEqual(
      rows.map((r) => r.id),
      ids,
    );
    for (const r of rows) {
      assert.equal(r.state, 'done', JSON.stringify(r));
      assert.equal(r.completions, 1, JSON.stringify(r));
      assert.ok(r.attempts === 1 || r.attempts === 2, JSON.stringify(r));
    }
    for (const id of orphaned) {
      const r = rows.find((x) => x.id === id);
      assert.equal(r.attempts, 2, `job ${id} held by the killed server: ${JSON.stringify(r)}`);
      const j = (await api(a, 'GET', `/api/v1/plans/${id}`)).json;
      assert.equal(j.state, 'done');
      assert.equal(j.attempts, 2);
    }
    assert.ok(rows.some((r) => r.attempts === 2));
    await a.stop();
    running.delete(a);
  });
});
