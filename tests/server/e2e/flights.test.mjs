// Flights through the real `uavcover serve`: the example olive grove with a fourth UAV is planned, then
// flown by a simulated fleet the server starts (speedup 50), followed over the events WebSocket until it
// is done. Every coverage waypoint ends reached, the log has them, and the measured numbers (events per
// second on the WebSocket, flight-log bytes per UAV-hour) are printed as one "flight-measure:" line.
import { describe, it, before, after } from 'node:test';
import assert from 'node:assert/strict';
import {
  api,
  assertError,
  createMission,
  eachBackend,
  enableSchemaChecks,
  EventSocket,
  freshDb,
  oliveGrove,
  postPlan,
  startServer,
  waitDone,
} from './harness.mjs';

const SPEEDUP = 50;

function fourUavGrove() {
  const doc = oliveGrove();
  doc.name = 'Olive grove, four UAVs';
  doc.uavs.push({ id: 'delta', start: [22.905, 40.5995], speed_mps: 6, max_accel_mps2: 2.5, endurance_min: 30 });
  for (const u of doc.uavs) u.share = 0.25;
  return doc;
}

async function command(server, id, body) {
  const res = await api(server, 'POST', `/api/v1/flights/${id}/commands`, { body });
  assert.equal(res.status, 202, res.text);
  return res.json;
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

  it('refuses flights of plans that are not done, and bad requests, naming the field', async () => {
    const missionId = await createMission(server, fourUavGrove());
    const plan = await postPlan(server, missionId, { seed: 3 });
    assertError(await api(server, 'POST', '/api/v1/plans/987654/flights', { body: { simulate: {} } }), 404, 'id');
    await waitDone(server, plan.id, { timeoutMs: 300000 });
    assertError(await api(server, 'POST', `/api/v1/plans/${plan.id}/flights`, { body: { simulate: { speedup: 5000 } } }), 422, 'simulate.speedup');
    assertError(
      await api(server, 'POST', `/api/v1/plans/${plan.id}/flights`, { body: { vehicles: [{ uav: 'alpha', endpoint: 'udp:192.0.2.1:14550' }] } }),
      422,
      'vehicles[0].endpoint',
    );
  });

  it('flies the four-UAV olive grove with a simulated fleet, followed over the WebSocket, to done', async () => {
    const missionId = await createMission(server, fourUavGrove());
    const plan = await postPlan(server, missionId, { seed: 7 });
    const done = await waitDone(server, plan.id, { timeoutMs: 300000 });
    assert.equal(done.state, 'done', JSON.stringify(done.error));

    const created = await api(server, 'POST', `/api/v1/plans/${plan.id}/flights`, { body: { simulate: { speedup: SPEEDUP } } });
    assert.equal(created.status, 201, created.text);
    const flight = created.json;
    assert.equal(flight.state, 'created');
    assert.equal(flight.uavs.length, 4);
    const sizes = Object.fromEntries(flight.uavs.map((u) => [u.uav, u.waypoints.length]));

    const ws = await EventSocket.open(server);
    let bytes = 0;
    ws.ws.on('message', (data) => {
      bytes += data.length;
    });
    ws.send({ subscribe: { flights: [flight.id] } });
    await ws.waitFor((m) => m.type === 'flight' && m.flight.id === flight.id);
    const t0 = Date.now();
    await command(server, flight.id, { command: 'upload' });
    await ws.waitFor((m) => m.type === 'flight' && m.flight.state === 'ready', 120000);
    await command(server, flight.id, { command: 'start' });
    const end = await ws.waitFor((m) => m.type === 'flight' && (m.flight.state === 'done' || m.flight.state === 'aborted'), 900000);
    const seconds = (Date.now() - t0) / 1000;
    ws.close();
    assert.equal(end.flight.state, 'done', JSON.stringify(end.flight.alerts));
    for (const u of end.flight.uavs) assert.equal(u.waypoints, 'R'.repeat(sizes[u.uav]), `${u.uav}: ${u.waypoints}`);
    const messages = ws.messages.filter((m) => m.type === 'flight' && m.flight.id === flight.id);
    // at most one message per 200 ms for the flight (plus the first answers to the subscription)
    assert.ok(messages.length <= seconds / 0.2 + 3, `${messages.length} messages in ${seconds} s`);

    // the log: every waypoint reached; its size per UAV-hour of simulated flight
    const reached = new Map();
    let logBytes = 0;
    let telemetryBytes = 0;
    let telemetry = 0;
    let records = 0;
    const span = new Map(); // per UAV: first and last telemetry time while armed
    for (let after = 0; ; ) {
      const page = await api(server, 'GET', `/api/v1/flights/${flight.id}/log?limit=1000&after=${after}`);
      assert.equal(page.status, 200, page.text);
      for (const r of page.json.items) {
        const size = Buffer.byteLength(JSON.stringify(r));
        logBytes += size;
        records += 1;
        if (r.kind === 'waypoint' && r.data.status === 'R') {
          if (!reached.has(r.uav)) reached.set(r.uav, new Set());
          reached.get(r.uav).add(r.data.waypoint);
        }
        if (r.kind === 'telemetry') {
          telemetry += 1;
          telemetryBytes += size;
          if (r.data.armed) {
            const t = Date.parse(r.t);
            const s = span.get(r.uav) ?? [t, t];
            span.set(r.uav, [Math.min(s[0], t), Math.max(s[1], t)]);
          }
        }
      }
      if (page.json.next_after === null) break;
      after = page.json.next_after;
    }
    for (const [uav, n] of Object.entries(sizes)) assert.equal(reached.get(uav)?.size, n, uav);
    const uavHours = [...span.values()].reduce((s, [a, b]) => s + ((b - a) / 1000) * SPEEDUP, 0) / 3600;
    const csv = await api(server, 'GET', `/api/v1/flights/${flight.id}/log.csv`);
    assert.equal(csv.status, 200);
    const measure = {
      backend,
      speedup: SPEEDUP,
      wall_s: Number(seconds.toFixed(1)),
      ws_flight_messages: messages.length,
      ws_messages_per_s: Number((messages.length / seconds).toFixed(2)),
      ws_bytes_per_s: Math.round(bytes / seconds),
      log_records: records,
      log_json_bytes: logBytes,
      log_csv_bytes: csv.bytes.length,
      uav_hours_simulated: Number(uavHours.toFixed(3)),
      log_json_bytes_per_uav_hour: Math.round(logBytes / uavHours),
      // at speedup 1 telemetry is kept once per wall second (log_period_s 1): SPEEDUP times as many
      // telemetry records per simulated hour as here
      log_json_bytes_per_uav_hour_realtime: Math.round((logBytes - telemetryBytes + telemetryBytes * SPEEDUP) / uavHours),
      telemetry_records: telemetry,
    };
    console.log(`flight-measure: ${JSON.stringify(measure)}`);
  });
});
