// Benchmark: the Fly tab following a simulated fleet of N UAVs (default 12) through the real server,
// in headless Chromium. Measures, does not assert: flight events per second received over the events
// WebSocket, the page's main-thread time per event and as a share of wall time (Chrome's
// Performance.getMetrics TaskDuration / ScriptDuration), and frame intervals (requestAnimationFrame)
// while the fleet flies. Writes bench/results/web-fly.md.
//
//   node bench/web/fly-live.mjs [--uavs 12] [--speedup 5] [--seconds 15] [--out bench/results/web-fly.md]
// Needs build/uavcover (UAVCOVER_CLI) and web/dist (scripts/build-web).
//
// The mission: the olive grove example's field with N UAVs spread along its south and north edges,
// equal shares, flown at 30 m: each UAV transits at its own altitude 5 m or more above the previous one
// under the 120 m ceiling (docs/exports.md), which allows 13 UAVs at most.
import { cpus, loadavg } from 'node:os';
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import * as h from '../../web/tests/e2e/harness.mjs';

const arg = (name, fallback) => {
  const i = process.argv.indexOf(`--${name}`);
  return i > 0 ? process.argv[i + 1] : fallback;
};
const nUavs = Number(arg('uavs', 12));
const speedup = Number(arg('speedup', 5));
const seconds = Number(arg('seconds', 15));
const outFile = arg('out', join(h.repo, 'bench/results/web-fly.md'));

const example = JSON.parse(readFileSync(join(h.repo, 'examples/olive-grove.json'), 'utf8'));
const mission = {
  ...example,
  name: `bench: olive grove, ${nUavs} UAVs`,
  camera: { ...example.camera, altitude_m: 30 },
  uavs: Array.from({ length: nUavs }, (_, i) => {
    const half = Math.ceil(nUavs / 2);
    const south = i < half;
    const f = (south ? i : i - half) / Math.max(1, half - 1);
    return { id: `u${i + 1}`, start: [+(22.8995 + f * 0.013).toFixed(6), south ? 40.5995 : 40.609], share: 1 / nUavs, speed_mps: 6, max_accel_mps2: 2.5, endurance_min: 30 };
  }),
};
delete mission.seed;

const quantile = (xs, q) => {
  const s = [...xs].sort((a, b) => a - b);
  return s.length ? s[Math.min(s.length - 1, Math.floor(q * (s.length - 1)))] : NaN;
};

const server = await h.startServer();
const browser = await h.launchBrowser();
try {
  const created = await server.api('/missions', { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(mission) });
  const missionId = created.id;
  let plan = await server.api(`/missions/${missionId}/plans`, { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: '{}' });
  while (plan.state !== 'done') {
    if (plan.state === 'failed' || plan.state === 'cancelled') throw new Error(`the plan ${plan.state}: ${JSON.stringify(plan.error)}`);
    await new Promise((r) => setTimeout(r, 500));
    plan = await server.api(`/plans/${plan.id}`);
  }
  const paths = await server.api(`/plans/${plan.id}/paths.geojson`);
  const waypoints = paths.features.filter((f) => f.properties.kind === 'coverage').reduce((n, f) => n + f.geometry.coordinates.length, 0);

  const { page } = await h.openPage(browser);
  // count the flight messages the page receives
  await page.addInitScript(() => {
    window.__flightEvents = 0;
    const Native = window.WebSocket;
    window.WebSocket = class extends Native {
      constructor(...a) {
        super(...a);
        this.addEventListener('message', (e) => {
          if (String(e.data).startsWith('{"flight"') || String(e.data).includes('"type":"flight"')) window.__flightEvents++;
        });
      }
    };
  });
  await page.goto(`${server.base}/?tiles=off&mission=${missionId}#fly`);
  await page.waitForFunction(() => /^Plan #\d+ \(/.test(document.querySelector('[data-testid=fly-plan]')?.textContent ?? ''), null, { timeout: 60000 });
  await page.fill('[data-testid=fly-speedup]', String(speedup));
  await page.click('[data-testid=fly-simulate]');
  await page.waitForSelector('[data-testid=fly-state][data-state=flying]', { timeout: 60000 });
  await page.waitForFunction((n) => document.querySelectorAll('[data-testid=fly-uav-marker]').length === n, nUavs, { timeout: 60000 });

  const cdp = await page.context().newCDPSession(page);
  await cdp.send('Performance.enable');
  const metrics = async () => Object.fromEntries((await cdp.send('Performance.getMetrics')).metrics.map((m) => [m.name, m.value]));
  const m0 = await metrics();
  const e0 = await page.evaluate(() => window.__flightEvents);
  const t0 = Date.now();
  const frames = await page.evaluate(
    (ms) =>
      new Promise((ok) => {
        const ts = [];
        const end = performance.now() + ms;
        const step = (t) => {
          ts.push(t);
          if (t < end) requestAnimationFrame(step);
          else ok(ts.slice(1).map((x, i) => x - ts[i]));
        };
        requestAnimationFrame(step);
      }),
    seconds * 1000,
  );
  const wall = (Date.now() - t0) / 1000;
  const m1 = await metrics();
  const e1 = await page.evaluate(() => window.__flightEvents);
  const state = await page.locator('[data-testid=fly-state]').getAttribute('data-state');
  mkdirSync(h.shots, { recursive: true });
  await h.shot(page, `bench-fly-${nUavs}-uavs`);

  const events = e1 - e0;
  const task = m1.TaskDuration - m0.TaskDuration;
  const script = m1.ScriptDuration - m0.ScriptDuration;
  const layout = m1.LayoutDuration - m0.LayoutDuration + (m1.RecalcStyleDuration - m0.RecalcStyleDuration);
  const lines = [
    `# Fly tab: live updates of a simulated fleet`,
    '',
    `\`node bench/web/fly-live.mjs --uavs ${nUavs} --speedup ${speedup} --seconds ${seconds}\`, ${new Date().toISOString().slice(0, 10)}, ` +
      `${cpus().length} cores (${cpus()[0]?.model.trim()}), load average ${loadavg()[0].toFixed(2)} at the end; headless Chromium without GPU, ` +
      `the real server and its simulated fleet on the same machine.`,
    '',
    `The olive grove field with ${nUavs} UAVs: ${waypoints} coverage waypoints on the map. Flight state during the window: ${state}.`,
    '',
    '| measure | value |',
    '|---|---|',
    `| window | ${wall.toFixed(1)} s |`,
    `| flight events received (WebSocket) | ${events} (${(events / wall).toFixed(1)} /s; each carries all ${nUavs} UAVs) |`,
    `| main-thread busy (TaskDuration) | ${(task * 1000).toFixed(0)} ms = ${((100 * task) / wall).toFixed(1)} % of wall time |`,
    `| of which script | ${(script * 1000).toFixed(0)} ms |`,
    `| of which style and layout | ${(layout * 1000).toFixed(0)} ms |`,
    `| main-thread time per flight event | ${events ? ((task * 1000) / events).toFixed(1) : '—'} ms |`,
    `| frames | ${frames.length} (${(frames.length / wall).toFixed(1)} fps) |`,
    `| frame interval p50 / p95 / max | ${quantile(frames, 0.5).toFixed(1)} / ${quantile(frames, 0.95).toFixed(1)} / ${Math.max(...frames).toFixed(1)} ms |`,
    '',
  ];
  mkdirSync(dirname(outFile), { recursive: true });
  writeFileSync(outFile, lines.join('\n'));
  console.log(lines.join('\n'));
} finally {
  await browser.close();
  await server.stop();
}
