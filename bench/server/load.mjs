// Load helpers for bench/server/run.sh (Node.js 20, no packages):
//   node load.mjs fill URL COUNT CONCURRENCY MISSION.json   stores COUNT missions; prints "FIRST_ID LAST_ID"
//   node load.mjs jobs URL MISSION.json COUNT               queues COUNT plan jobs of the mission, waits
//                                                           until all are done; prints "SECONDS DONE FAILED"
//   node load.mjs requests URL                              the requests served so far (from /metrics)
import fs from 'node:fs';

const [cmd, base, ...rest] = process.argv.slice(2);

async function post(path, body) {
  const r = await fetch(base + path, {
    method: 'POST',
    headers: { 'content-type': 'application/json' },
    body: JSON.stringify(body),
  });
  const text = await r.text();
  if (r.status >= 300) throw new Error(`POST ${path}: ${r.status} ${text}`);
  return JSON.parse(text);
}

async function fill(count, concurrency, file) {
  const doc = JSON.parse(fs.readFileSync(file, 'utf8'));
  let next = 0;
  let first = Infinity;
  let last = 0;
  const worker = async () => {
    for (;;) {
      const i = next++;
      if (i >= count) return;
      const { id } = await post('/api/v1/missions', { ...doc, name: `bench mission ${i}` });
      first = Math.min(first, id);
      last = Math.max(last, id);
    }
  };
  await Promise.all(Array.from({ length: concurrency }, worker));
  console.log(`${first} ${last}`);
}

async function jobs(file, count) {
  const doc = JSON.parse(fs.readFileSync(file, 'utf8'));
  const { id: mission } = await post('/api/v1/missions', doc);
  const t0 = performance.now();
  const ids = [];
  for (let i = 0; i < count; i++) ids.push((await post(`/api/v1/missions/${mission}/plans`, { seed: i + 1 })).id);
  const open = new Set(ids);
  let done = 0;
  let failed = 0;
  while (open.size > 0) {
    for (const id of [...open]) {
      const j = await (await fetch(`${base}/api/v1/plans/${id}`)).json();
      if (['done', 'failed', 'cancelled'].includes(j.state)) {
        open.delete(id);
        if (j.state === 'done') done++;
        else failed++;
      }
    }
    if (open.size > 0) await new Promise((r) => setTimeout(r, 100));
  }
  const seconds = (performance.now() - t0) / 1000;
  console.log(`${seconds.toFixed(2)} ${done} ${failed}`);
}

async function requests() {
  const text = await (await fetch(`${base}/metrics`)).text();
  let total = 0;
  for (const line of text.split('\n')) {
    // labels may hold braces (route="/api/v1/missions/{id}"): the value is the line's last field
    if (line.startsWith('uavcover_http_requests_total')) total += Number(line.trim().split(/\s+/).pop());
  }
  console.log(String(Math.round(total)));
}

if (cmd === 'fill') await fill(Number(rest[0]), Number(rest[1]), rest[2]);
else if (cmd === 'jobs') await jobs(rest[0], Number(rest[1]));
else if (cmd === 'requests') await requests();
else {
  console.error('usage: load.mjs fill|jobs|requests URL ...');
  process.exit(2);
}
