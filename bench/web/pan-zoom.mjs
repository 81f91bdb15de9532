// Benchmark: a plan with over 100 000 path vertices in the web app's Plan tab, panned and zoomed in
// headless Chromium. Measures, does not assert: the time from navigation to the plan drawn, and the
// frame times (requestAnimationFrame timestamps collected in the page) during a scripted sequence of
// wheel zooms and drags. Writes bench/results/web.md.
//
//   node bench/web/pan-zoom.mjs [--side-m 2100] [--gap-m 20] [--out bench/results/web.md] [--db FILE]
// --db keeps the SQLite database, and a later run with the same file reuses its plan (planning it takes
// minutes on a loaded 2-core machine).
// Needs build/uavcover (UAVCOVER_CLI) and web/node_modules; runs `npm run build` in web/ first.
//
// The mission: a square field with diagonal hedges (thin no-fly zones at 45° to the grid): DARP's STC
// loops follow each hedge as a staircase, so the paths have many turning waypoints (the real count is
// read from paths.geojson).
import { execFileSync } from 'node:child_process';
import { cpus, loadavg, totalmem } from 'node:os';
import { mkdirSync, readFileSync, statSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import * as h from '../../web/tests/e2e/harness.mjs';

const arg = (name, fallback) => {
  const i = process.argv.indexOf(`--${name}`);
  return i > 0 ? process.argv[i + 1] : fallback;
};
const sideM = Number(arg('side-m', 2100));
const gapM = Number(arg('gap-m', 20));
const outFile = arg('out', join(h.repo, 'bench/results/web.md'));
const cliPlan = arg('cli-plan', null); // a folder of `uavcover plan --no-images --no-evaluate` of the same field
const dbFile = arg('db', null); // keep the database: a later run reuses its plan instead of planning again

const lat0 = 40.6, lon0 = 22.9;
const pos = (x, y) => [+(lon0 + x / (111320 * Math.cos((lat0 * Math.PI) / 180))).toFixed(7), +(lat0 + y / 110540).toFixed(7)];

/** The field: a square of sideM metres, hedges 1 m wide along x - y = c every gapM metres of c. */
function hedgeField() {
  const W = sideM, m = 6, half = Math.SQRT1_2; // horizontal half-width: hedges 1 m wide
  const zones = [];
  for (let c = -W + gapM; c < W - gapM; c += gapM) {
    const y0 = Math.max(m, m - c), y1 = Math.min(W - m, W - m - c);
    if (y1 - y0 <= 20) continue;
    const p0 = [y0 + c, y0], p1 = [y1 + c, y1];
    zones.push({ type: 'Polygon', coordinates: [[pos(p0[0] - half, p0[1]), pos(p0[0] + half, p0[1]), pos(p1[0] + half, p1[1]), pos(p1[0] - half, p1[1])]] });
  }
  return {
    name: `bench: hedged field ${W} m`,
    area: { type: 'Polygon', coordinates: [[pos(0, 0), pos(W, 0), pos(W, W), pos(0, W)]] },
    no_fly_zones: zones,
    spacing_m: 4,
    // one UAV: the exports' separation check between UAVs takes tens of minutes on paths this long
    uavs: [{ id: 'a', start: pos(-20, -20) }],
    planner: 'darp',
    planner_params: { optimise_placement: false, max_iterations: 300 },
  };
}

const quantile = (xs, q) => {
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.floor(q * (s.length - 1)))];
};
const ms = (x) => `${x.toFixed(1)} ms`;

// 1. the app's bundle size, from Vite's own report
const build = execFileSync('npm', ['run', 'build'], { cwd: join(h.repo, 'web'), encoding: 'utf8' });
const jsLine = build.split('\n').filter((l) => /assets\/.*\.js\s/.test(l)).map((l) => l.replace(/\x1b\[[0-9;]*m/g, '').trim()).join('\n    ') || '(not found)';

// 2. the server and the plan
const server = await h.startServer({ workers: 2, db: dbFile });
const browser = await h.launchBrowser();
let report = '';
try {
  const t0 = Date.now();
  const doc = hedgeField();
  const json = { method: 'POST', headers: { 'content-type': 'application/json' } };
  // a plan of this field from an earlier run with --db
  let missionId = null, job = null, reused = false;
  for (const m of (await server.api(`/missions?name=${encodeURIComponent(doc.name)}`)).items) {
    const done = (await server.api(`/missions/${m.id}/plans`)).items.find((p) => p.state === 'done');
    if (done && m.name === doc.name) {
      missionId = m.id;
      job = await server.api(`/plans/${done.id}`);
      reused = true;
      break;
    }
  }
  if (!job && cliPlan) {
    // the server's exports of a path this long take too long on a loaded machine: plan the seeded
    // example through the API and hand the app the CLI's plan.json and paths.geojson of the big field
    missionId = (await server.api('/missions?name=olive')).items[0].id;
    job = await server.api(`/missions/${missionId}/plans`, { ...json, body: '{}' });
  }
  if (!job) {
    missionId = (await server.api('/missions', { ...json, body: JSON.stringify(doc) })).id;
    job = await server.api(`/missions/${missionId}/plans`, { ...json, body: '{}' });
  }
  while (!['done', 'failed', 'cancelled'].includes(job.state)) {
    await new Promise((r) => setTimeout(r, 1000));
    job = await server.api(`/plans/${job.id}`);
  }
  if (job.state !== 'done') throw new Error(`the plan ${job.state}: ${JSON.stringify(job.error)}`);
  const planS = (Date.now() - t0) / 1000;
  const paths = cliPlan ? JSON.parse(readFileSync(join(cliPlan, 'paths.geojson'), 'utf8')) : await server.api(`/plans/${job.id}/paths.geojson`);
  const lines = paths.features.filter((f) => f.geometry.type === 'LineString');
  const vertices = lines.reduce((n, f) => n + f.geometry.coordinates.length, 0);
  const sizes = {};
  for (const name of ['plan.json', 'paths.geojson'])
    sizes[name] = cliPlan ? statSync(join(cliPlan, name)).size : job.artifacts.find((a) => a.name === name)?.size ?? 0;
  console.log(`plan #${job.id}: ${vertices} path vertices in ${lines.length} parts, planned in ${planS.toFixed(0)} s`);

  // 3. the app: first draw, then frames while zooming and panning
  const { page, problems } = await h.openPage(browser, { width: 1280, height: 800 });
  if (cliPlan)
    for (const name of ['plan.json', 'paths.geojson'])
      await page.route(`**/api/v1/plans/${job.id}/${name}`, (r) => r.fulfill({ path: join(cliPlan, name), contentType: 'application/json' }));
  const nav0 = Date.now();
  await page.goto(`${server.base}/?tiles=off&mission=${missionId}#plan`);
  await page.waitForSelector(`[data-testid=metrics-panel][data-plan-id="${job.id}"]`, { timeout: 120000 });
  await h.planDrawn(page);
  const firstDrawMs = Date.now() - nav0;
  const legend = await page.locator('[data-testid=plan-legend-item]').allInnerTexts();
  await page.waitForTimeout(500);
  await h.shot(page, 'bench-100k-plan');

  const box = await page.locator('#map').boundingBox();
  const cx = box.x + box.width / 2, cy = box.y + box.height / 2;
  const run = async (label, steps) => {
    await page.evaluate(() => {
      window.__frames = [];
      window.__recording = true;
      const tick = (t) => {
        window.__frames.push(t);
        if (window.__recording) requestAnimationFrame(tick);
      };
      requestAnimationFrame(tick);
    });
    await steps();
    await page.waitForTimeout(300); // the last animation settles
    const frames = await page.evaluate(() => {
      window.__recording = false;
      return window.__frames;
    });
    const dt = frames.slice(1).map((t, i) => t - frames[i]);
    return { label, frames: dt.length, median: quantile(dt, 0.5), p95: quantile(dt, 0.95), max: Math.max(...dt), over50: dt.filter((d) => d > 50).length };
  };
  const wheel = async (dy, n) => {
    for (let i = 0; i < n; i++) {
      await page.mouse.move(cx + 40, cy - 30);
      await page.mouse.wheel(0, dy);
      await page.waitForTimeout(350); // Leaflet's zoom animation is 250 ms
    }
  };
  const drag = async (n) => {
    for (let i = 0; i < n; i++) {
      const dx = i % 2 ? -220 : 260, dy = i % 3 ? 120 : -140;
      await page.mouse.move(cx, cy);
      await page.mouse.down();
      await page.mouse.move(cx + dx, cy + dy, { steps: 20 });
      await page.mouse.up();
      await page.waitForTimeout(100);
    }
  };
  const results = [];
  results.push(await run('pan, whole plan in view (6 drags)', () => drag(6)));
  results.push(await run('zoom in 4 steps (wheel)', () => wheel(-100, 4)));
  results.push(await run('pan, zoomed in (6 drags)', () => drag(6)));
  results.push(await run('zoom in to labels (3 steps), pan (4 drags)', async () => { await wheel(-100, 3); await drag(4); }));
  results.push(await run('zoom out 7 steps (wheel)', () => wheel(100, 7)));
  const all = results.reduce((a, r) => a.concat([r]), []);
  await h.shot(page, 'bench-100k-after');
  console.table(all);

  const cpu = cpus()[0]?.model ?? 'unknown CPU';
  const chromium = execFileSync(process.env.CHROMIUM || '/usr/bin/chromium', ['--version'], { encoding: 'utf8' }).trim();
  const now = new Date().toISOString().replace('T', ' ').slice(0, 16);
  report = `# Web app benchmark: a plan with ${vertices.toLocaleString('en')} path vertices

Generated by \`node bench/web/pan-zoom.mjs\` on ${now} UTC, on ${cpus().length} cores (${cpu}),
${(totalmem() / 2 ** 30).toFixed(0)} GiB; load average at the end: ${loadavg().map((x) => x.toFixed(2)).join(' ')} (the machine is shared).
Browser: ${chromium}, headless, no GPU (\`--disable-gpu\`: software rasterising), 1280×800, tiles off.
Server: \`uavcover serve\` on 127.0.0.1 with a temporary SQLite database, 2 workers.

## The plan

A ${sideM} m square field with ${doc.no_fly_zones.length} diagonal hedges (1 m wide no-fly zones every ${(gapM / Math.SQRT2).toFixed(1)} m,
at 45° to the DARP grid), spacing 4 m, one UAV, \`darp\` without placement search: STC loops follow
each hedge as a staircase, so the paths turn often. ${cliPlan ? `The server's plan job of a field this size spent over 20 minutes in its exports stage (the no-fly and separation checks of the mission items) on the loaded machine, so this run plans the seeded example through the API (job #${job.id}) and hands the app the \`plan.json\` and \`paths.geojson\` of \`uavcover plan --no-images --no-evaluate\` of the big field (Playwright \`page.route\` for those two files only).` : reused ? `Planned by an earlier run (job #${job.id}, reused with \`--db\`).` : `Planned by the server in ${planS.toFixed(0)} s (job #${job.id}), while other builds loaded the machine.`}

- path vertices (LineString positions in \`paths.geojson\`): **${vertices.toLocaleString('en')}** in ${lines.length} parts
- \`paths.geojson\` ${(sizes['paths.geojson'] / 2 ** 20).toFixed(1)} MiB, \`plan.json\` ${(sizes['plan.json'] / 2 ** 20).toFixed(1)} MiB
- legend: ${legend.map((l) => l.replace(/\s+/g, ' ')).join('; ')}

## Time to first draw

From \`page.goto(/?tiles=off&mission=ID#plan)\` to the plan's metrics panel shown and every plan tile
in view drawn (\`harness.planDrawn\`: page load, the mission, its plan list, \`GET /plans/{id}\`,
\`plan.json\` and \`paths.geojson\` parsed in the drawing worker, the tiles): **${(firstDrawMs / 1000).toFixed(2)} s**.

## Frame times while panning and zooming

requestAnimationFrame timestamps recorded in the page during each scripted sequence (Playwright mouse
wheel and drags; each wheel step is one zoom level, animated by Leaflet):

| sequence | frames | median | p95 | max | frames > 50 ms |
|---|---:|---:|---:|---:|---:|
${all.map((r) => `| ${r.label} | ${r.frames} | ${ms(r.median)} | ${ms(r.p95)} | ${ms(r.max)} | ${r.over50} |`).join('\n')}

Console errors or warnings during the run: ${problems.length ? problems.join('; ') : 'none'}.

## Bundle

\`npm run build\` (Vite) reports for the app's JavaScript:

    ${jsLine}

Screenshots: \`build/web-screenshots/bench-100k-plan.png\` (the whole plan), \`bench-100k-after.png\`.
`;
} finally {
  await browser.close();
  await server.stop();
}
mkdirSync(dirname(outFile), { recursive: true });
writeFileSync(outFile, report);
console.log(`wrote ${outFile}`);
