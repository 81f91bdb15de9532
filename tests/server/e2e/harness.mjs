// Harness for the end-to-end tests of `uavcover serve`: starts the real binary on loopback (SQLite or
// PostgreSQL), talks to it with fetch, WebSocket (ws) and SSE, and checks responses against the
// server's own OpenAPI document (swagger-parser + ajv). Node.js 20, node:test.
//
// Environment:
//   UAVCOVER_CLI               the uavcover binary (default: <repo>/build/uavcover)
//   UAVCOVER_TEST_PG_URL_FILE  a file holding a libpq URI of a throwaway PostgreSQL cluster
//                              (scripts/pg-test-cluster, the CTest fixture `pg`); unset: SQLite only
import { spawn, spawnSync } from 'node:child_process';
import { createRequire } from 'node:module';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import http from 'node:http';
import { fileURLToPath } from 'node:url';
import assert from 'node:assert/strict';

export const REPO = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../../..');
// the npm packages live in tests/node (installed by scripts/setup with `npm ci`)
const requireNode = createRequire(path.join(REPO, 'tests/node/package.json'));
export const WebSocket = requireNode('ws');
const SwaggerParser = requireNode('@apidevtools/swagger-parser');
const Ajv = requireNode('ajv');
const addFormats = requireNode('ajv-formats');

export const CLI = process.env.UAVCOVER_CLI || path.join(REPO, 'build/uavcover');
export const EXAMPLES = path.join(REPO, 'examples');

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// ---------------------------------------------------------------- temp folders, databases

const tempDirs = [];
export function tempDir(prefix = 'uavcover-e2e-') {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), prefix));
  tempDirs.push(dir);
  return dir;
}
process.on('exit', () => {
  if (process.env.UAVCOVER_E2E_KEEP) return;
  for (const d of tempDirs) fs.rmSync(d, { recursive: true, force: true });
});

/** The backends the suites run against: SQLite always, PostgreSQL when the fixture's URL file is set. */
export function backends() {
  const list = ['sqlite'];
  if (process.env.UAVCOVER_TEST_PG_URL_FILE) list.push('postgresql');
  return list;
}

function pgClusterUrl() {
  const file = process.env.UAVCOVER_TEST_PG_URL_FILE;
  assert.ok(file, 'UAVCOVER_TEST_PG_URL_FILE is not set');
  assert.ok(fs.existsSync(file), `${file} does not exist: start the cluster (scripts/pg-test-cluster start DIR)`);
  return fs.readFileSync(file, 'utf8').trim();
}

/** The URI of database `name` on the same cluster as `url` (libpq URI, path = database). */
export function pgUrlFor(url, name) {
  const m = url.match(/^(postgres(?:ql)?:\/\/[^/?]*)(\/[^?]*)?(\?.*)?$/);
  assert.ok(m, `not a libpq URI: ${url}`);
  return `${m[1]}/${name}${m[3] || ''}`;
}

export function psql(url, sql) {
  const r = spawnSync('psql', [url, '-v', 'ON_ERROR_STOP=1', '-qAt', '-F', '\t', '-c', sql], {
    encoding: 'utf8',
  });
  if (r.status !== 0) throw new Error(`psql failed (${r.status}): ${r.stderr}`);
  return r.stdout
    .split('\n')
    .filter((l) => l.length > 0)
    .map((l) => l.split('\t'));
}

let dbCounter = 0;
/** A fresh, empty database: {url, backend, pg?} (a temp SQLite file, or a new PostgreSQL database). */
export function freshDb(backend) {
  if (backend === 'sqlite') {
    return { backend, url: `sqlite:${path.join(tempDir(), 'uavcover.db')}` };
  }
  const cluster = pgClusterUrl();
  const name = `e2e_${process.pid}_${Date.now().toString(36)}_${dbCounter++}`;
  psql(cluster, `CREATE DATABASE ${name}`);
  return { backend, url: pgUrlFor(cluster, name), name };
}

// ---------------------------------------------------------------- the server process

const servers = new Set();
process.on('exit', () => {
  for (const s of servers) {
    try {
      s.proc.kill('SIGKILL');
    } catch {
      /* gone */
    }
  }
});

export class Server {
  constructor(proc, url, output, token) {
    this.proc = proc;
    this.pid = proc.pid;
    this.url = url; // http://HOST:PORT
    this.output = output; // {stdout, stderr} collected so far
    this.token = token;
    this.exited = new Promise((resolve) => {
      if (proc.exitCode !== null || proc.signalCode !== null) resolve({ code: proc.exitCode, signal: proc.signalCode });
      else proc.once('exit', (code, signal) => resolve({ code, signal }));
    });
    this._contract = null;
  }
  get wsUrl() {
    return this.url.replace(/^http/, 'ws');
  }
  /** SIGTERM and wait for the exit (SIGKILL after `graceMs`). */
  async stop(graceMs = 10000) {
    if (this.proc.exitCode === null && this.proc.signalCode === null) this.proc.kill('SIGTERM');
    const t = setTimeout(() => this.proc.kill('SIGKILL'), graceMs);
    const r = await this.exited;
    clearTimeout(t);
    servers.delete(this);
    return r;
  }
  /** kill -9, as a crash. */
  async kill() {
    this.proc.kill('SIGKILL');
    const r = await this.exited;
    servers.delete(this);
    return r;
  }
  /** The OpenAPI contract served by this server (fetched, validated and dereferenced once). */
  async contract() {
    if (!this._contract) this._contract = await Contract.load(this);
    return this._contract;
  }
}

/** Runs `uavcover serve ARGS` to its end (for start-up refusals): {code, signal, stdout, stderr}. */
export function runServe(args, timeoutMs = 20000) {
  const r = spawnSync(CLI, ['serve', ...args], { encoding: 'utf8', timeout: timeoutMs });
  return { code: r.status, signal: r.signal, stdout: r.stdout, stderr: r.stderr };
}

/** `--lease-ms MS` when the server offers it (a test option), so expired leases come back soon; else []. */
export function leaseArgs(ms) {
  const help = runServe(['--help']);
  return /--lease-ms/.test(help.stdout + help.stderr) ? ['--lease-ms', String(ms)] : [];
}

/**
 * Starts `uavcover serve --listen 127.0.0.1:0 --db DB --seed-dir examples ARGS` and waits for its
 * line "uavcover: serving on http://HOST:PORT ...". Options: db (from freshDb), args (extra), token
 * (sent by api() as a bearer token), listen, seed (false: no --seed-dir).
 */
/** env: extra environment variables of the server (e.g. the test hook UAVCOVER_TEST_HOLD_STAGE). */
export async function startServer({ db, args = [], token, listen = '127.0.0.1:0', seed = true, timeoutMs = 30000, env = {} } = {}) {
  const argv = ['serve', '--listen', listen, '--db', db.url];
  if (seed) argv.push('--seed-dir', EXAMPLES);
  argv.push(...args);
  const proc = spawn(CLI, argv, { stdio: ['ignore', 'pipe', 'pipe'], env: { ...process.env, ...env } });
  const output = { stdout: '', stderr: '' };
  proc.stdout.setEncoding('utf8');
  proc.stderr.setEncoding('utf8');
  proc.stderr.on('data', (d) => {
    output.stderr += d;
    if (output.stderr.length > 1 << 20) output.stderr = output.stderr.slice(-(1 << 19));
  });
  const url = await new Promise((resolve, reject) => {
    const timer = setTimeout(() => {
      proc.kill('SIGKILL');
      reject(new Error(`uavcover serve printed no URL within ${timeoutMs} ms\nstdout: ${output.stdout}\nstderr: ${output.stderr}`));
    }, timeoutMs);
    const onData = (d) => {
      output.stdout += d;
      const m = output.stdout.match(/uavcover: serving on (http:\/\/[^\s/]+)/);
      if (m) {
        clearTimeout(timer);
        resolve(m[1]);
      }
      if (output.stdout.length > 1 << 20) output.stdout = output.stdout.slice(-(1 << 19));
    };
    proc.stdout.on('data', onData);
    proc.once('exit', (code, signal) => {
      clearTimeout(timer);
      reject(new Error(`uavcover serve exited (${code ?? signal}) before serving\nstdout: ${output.stdout}\nstderr: ${output.stderr}`));
    });
  });
  const server = new Server(proc, url, output, token);
  servers.add(server);
  return server;
}

// ---------------------------------------------------------------- HTTP

/**
 * One request: {status, headers (Headers), text, json (parsed when JSON), bytes (Buffer)}.
 * opts: body (object -> JSON; string/Buffer sent as is), headers, token (overrides the server's;
 * null: none), check (default true: JSON answers are checked against the OpenAPI schemas when the
 * server's contract has been loaded).
 */
export async function api(server, method, pathname, opts = {}) {
  const headers = { ...(opts.headers || {}) };
  const token = opts.token !== undefined ? opts.token : server.token;
  if (token) headers.authorization = `Bearer ${token}`;
  let body = opts.body;
  if (body !== undefined && typeof body !== 'string' && !Buffer.isBuffer(body)) {
    body = JSON.stringify(body);
    if (!Object.keys(headers).some((h) => h.toLowerCase() === 'content-type')) headers['content-type'] = 'application/json';
  } else if (body !== undefined && !Object.keys(headers).some((h) => h.toLowerCase() === 'content-type')) {
    headers['content-type'] = 'application/json';
  }
  const res = await fetch(server.url + pathname, { method, headers, body, redirect: 'manual' });
  const bytes = Buffer.from(await res.arrayBuffer());
  const out = { status: res.status, headers: res.headers, bytes, text: bytes.toString('utf8'), json: undefined };
  const ct = res.headers.get('content-type') || '';
  if (ct.includes('json')) {
    try {
      out.json = JSON.parse(out.text);
    } catch {
      /* left undefined: the test asserts */
    }
  }
  if (opts.check !== false && server._contract && out.json !== undefined) {
    server._contract.check(method, pathname, out.status, out.json);
  }
  return out;
}

/**
 * A raw HTTP/1.1 request through node:http (for bodies fetch would refuse or streams it would buffer):
 * {status, headers (plain object), text, json}. expectContinue: send `Expect: 100-continue` and the
 * body only after the server's 100 (a server refusing the body answers at once instead).
 */
export function rawRequest(server, method, pathname, { headers = {}, body, expectContinue = false } = {}) {
  return new Promise((resolve, reject) => {
    const u = new URL(server.url); // the path goes out as given (no dot segments removed)
    const h = { ...headers };
    if (server.token && !h.authorization) h.authorization = `Bearer ${server.token}`;
    if (body !== undefined) h['content-length'] = Buffer.byteLength(body);
    if (expectContinue) h.expect = '100-continue';
    let answered = false;
    const req = http.request({ host: u.hostname, port: u.port, path: pathname, method, headers: h }, (res) => {
      answered = true;
      const chunks = [];
      res.on('data', (c) => chunks.push(c));
      res.on('end', () => {
        const text = Buffer.concat(chunks).toString('utf8');
        let json;
        try {
          json = JSON.parse(text);
        } catch {
          /* not JSON */
        }
        resolve({ status: res.statusCode, headers: res.headers, text, json });
      });
      res.on('error', () => resolve({ status: res.statusCode, headers: res.headers, text: '', json: undefined }));
    });
    req.on('error', (e) => {
      if (!answered) reject(e);
    });
    if (expectContinue) {
      req.on('continue', () => req.end(body));
      req.flushHeaders();
    } else if (body !== undefined) req.end(body);
    else req.end();
  });
}

/** Asserts the error body shape {"error": {"field": string, "message": string}} and no leak. */
export function assertError(res, status, field) {
  assert.equal(res.status, status, `expected ${status}, got ${res.status}: ${res.text}`);
  assert.match(res.headers.get ? res.headers.get('content-type') || '' : res.headers['content-type'] || '', /application\/json/);
  const j = res.json;
  assert.ok(j && typeof j === 'object', `error body is not JSON: ${res.text}`);
  assert.deepEqual(Object.keys(j), ['error'], `error body: ${res.text}`);
  assert.equal(typeof j.error.field, 'string', res.text);
  assert.equal(typeof j.error.message, 'string', res.text);
  assert.ok(j.error.message.length > 0, 'empty message');
  assertNoLeak(res.text);
  if (field !== undefined) assert.equal(j.error.field, field, `field of ${res.text}`);
  return j.error;
}

/** No internal file path, source file or stack trace in a response text. */
export function assertNoLeak(text) {
  assert.doesNotMatch(text, /\/(work|tmp|home|root|usr|src|build)\//, `internal path in ${text}`);
  assert.doesNotMatch(text, /\.(cpp|hpp|cc|h):\d+/, `source location in ${text}`);
  assert.doesNotMatch(text, /\bat \S+ \(|std::|terminate called|Traceback|what\(\):/, `stack trace in ${text}`);
}

// ---------------------------------------------------------------- missions and jobs

export function readJson(file) {
  return JSON.parse(fs.readFileSync(file, 'utf8'));
}
export const oliveGrove = () => readJson(path.join(EXAMPLES, 'olive-grove.json'));
export const rectangle = () => readJson(path.join(REPO, 'bench/data/mondinelli2025/rectangle_3uav.json'));

/** The olive grove with a fine grid: darp runs for seconds (spacing 2 m: ~10 s, 3 m: ~5 s alone on a core). */
export function slowMission(spacing = 2) {
  const m = oliveGrove();
  delete m.camera;
  m.altitude_m = 50;
  m.spacing_m = spacing;
  m.name = `slow olive grove ${spacing} m`;
  return m;
}

export async function createMission(server, doc) {
  const r = await api(server, 'POST', '/api/v1/missions', { body: doc });
  assert.equal(r.status, 201, r.text);
  return r.json.id;
}

export async function postPlan(server, missionId, params = {}) {
  const r = await api(server, 'POST', `/api/v1/missions/${missionId}/plans`, { body: params });
  assert.equal(r.status, 202, r.text);
  return r.json;
}

/** Polls GET /plans/{id} (or kind) until `pred(job)`; returns the job. */
export async function waitJob(server, id, pred, { timeoutMs = 60000, intervalMs = 50, kind = 'plans' } = {}) {
  const t0 = Date.now();
  let last;
  while (Date.now() - t0 < timeoutMs) {
    const r = await api(server, 'GET', `/api/v1/${kind}/${id}`);
    assert.equal(r.status, 200, r.text);
    last = r.json;
    if (pred(last)) return last;
    await sleep(intervalMs);
  }
  throw new Error(`job ${id} did not reach the state wanted within ${timeoutMs} ms; last: ${JSON.stringify(last)}`);
}
export const isTerminal = (j) => ['done', 'failed', 'cancelled'].includes(j.state);
export const waitDone = (server, id, opts) => waitJob(server, id, isTerminal, opts);

// ---------------------------------------------------------------- live events

/** A WebSocket client of /api/v1/events that collects messages. */
export class EventSocket {
  static async open(server) {
    const headers = server.token ? { authorization: `Bearer ${server.token}` } : {};
    const ws = new WebSocket(`${server.wsUrl}/api/v1/events`, { headers });
    const s = new EventSocket(ws);
    await new Promise((resolve, reject) => {
      ws.once('open', resolve);
      ws.once('error', reject);
      ws.once('unexpected-response', (_req, res) => reject(new Error(`WebSocket upgrade refused: ${res.statusCode}`)));
    });
    return s;
  }
  constructor(ws) {
    this.ws = ws;
    this.messages = [];
    this.waiters = [];
    ws.on('message', (data) => {
      const m = JSON.parse(data.toString('utf8'));
      this.messages.push(m);
      this.waiters = this.waiters.filter((w) => !w());
    });
  }
  send(obj) {
    this.ws.send(JSON.stringify(obj));
  }
  /** Resolves with the first message (already received or future) that satisfies pred. */
  waitFor(pred, timeoutMs = 60000) {
    return new Promise((resolve, reject) => {
      let done = false;
      const check = () => {
        if (done) return true;
        const m = this.messages.find(pred);
        if (m) {
          done = true;
          clearTimeout(t);
          resolve(m);
          return true;
        }
        return false;
      };
      const t = setTimeout(() => {
        done = true;
        reject(new Error(`no such WebSocket message within ${timeoutMs} ms; got ${JSON.stringify(this.messages).slice(0, 2000)}`));
      }, timeoutMs);
      if (!check()) this.waiters.push(check);
    });
  }
  close() {
    this.ws.close();
  }
}

/** An SSE client of /api/v1/events?jobs=...: parses `event:` / `data:` records from the body stream. */
export class EventStream {
  static async open(server, jobs) {
    const ac = new AbortController();
    const headers = { accept: 'text/event-stream' };
    if (server.token) headers.authorization = `Bearer ${server.token}`;
    const res = await fetch(`${server.url}/api/v1/events?jobs=${jobs.join(',')}`, { headers, signal: ac.signal });
    const s = new EventStream(res, ac);
    s._pump();
    return s;
  }
  constructor(res, ac) {
    this.res = res;
    this.ac = ac;
    this.records = []; // {event, data (parsed), raw}
    this.comments = 0;
    this.waiters = [];
    this.ended = false;
  }
  async _pump() {
    const decoder = new TextDecoder();
    let buf = '';
    try {
      for await (const chunk of this.res.body) {
        buf += decoder.decode(chunk, { stream: true });
        buf = buf.replace(/\r\n/g, '\n');
        let i;
        while ((i = buf.indexOf('\n\n')) >= 0) {
          const block = buf.slice(0, i);
          buf = buf.slice(i + 2);
          let event = 'message';
          const data = [];
          let any = false;
          for (const line of block.split('\n')) {
            if (line.startsWith(':')) {
              this.comments++;
              continue;
            }
            const c = line.indexOf(':');
            const field = c < 0 ? line : line.slice(0, c);
            let value = c < 0 ? '' : line.slice(c + 1);
            if (value.startsWith(' ')) value = value.slice(1);
            if (field === 'event') event = value;
            else if (field === 'data') data.push(value);
            any = true;
          }
          if (any && data.length) {
            const raw = data.join('\n');
            let parsed;
            try {
              parsed = JSON.parse(raw);
            } catch {
              parsed = undefined;
            }
            this.records.push({ event, data: parsed, raw });
            this.waiters = this.waiters.filter((w) => !w());
          }
        }
      }
    } catch {
      /* aborted */
    }
    this.ended = true;
    this.waiters = this.waiters.filter((w) => !w());
  }
  waitFor(pred, timeoutMs = 60000) {
    return new Promise((resolve, reject) => {
      let done = false;
      const check = () => {
        if (done) return true;
        const r = this.records.find(pred);
        if (r) {
          done = true;
          clearTimeout(t);
          resolve(r);
          return true;
        }
        if (this.ended) {
          done = true;
          clearTimeout(t);
          reject(new Error(`SSE stream ended; got ${JSON.stringify(this.records.map((x) => x.raw)).slice(0, 2000)}`));
          return true;
        }
        return false;
      };
      const t = setTimeout(() => {
        done = true;
        reject(new Error(`no such SSE record within ${timeoutMs} ms; got ${JSON.stringify(this.records.map((x) => x.raw)).slice(0, 2000)}`));
      }, timeoutMs);
      if (!check()) this.waiters.push(check);
    });
  }
  close() {
    this.ac.abort();
  }
}

// ---------------------------------------------------------------- OpenAPI contract

/**
 * OpenAPI 3.0 schema -> JSON Schema for ajv: `nullable: true` becomes a type that admits null, boolean
 * exclusiveMinimum/exclusiveMaximum become numbers.
 */
export function toJsonSchema(s) {
  if (Array.isArray(s)) return s.map(toJsonSchema);
  if (!s || typeof s !== 'object') return s;
  const out = {};
  for (const [k, v] of Object.entries(s)) {
    if (k === 'nullable' || k === 'example' || k === 'xml' || k === 'externalDocs' || k === 'discriminator') continue;
    if (k === 'properties' || k === 'patternProperties' || k === 'definitions' || k === '$defs') {
      out[k] = Object.fromEntries(Object.entries(v).map(([n, p]) => [n, toJsonSchema(p)]));
    } else out[k] = toJsonSchema(v);
  }
  // OpenAPI 3.0 (JSON Schema draft 4): exclusiveMinimum/Maximum are booleans qualifying minimum/maximum
  for (const [ex, bound] of [
    ['exclusiveMinimum', 'minimum'],
    ['exclusiveMaximum', 'maximum'],
  ]) {
    if (typeof s[ex] === 'boolean') {
      if (s[ex] && typeof s[bound] === 'number') {
        out[ex] = s[bound];
        delete out[bound];
      } else delete out[ex];
    }
  }
  if (s.nullable === true) {
    if (typeof out.type === 'string') out.type = [out.type, 'null'];
    else if (Array.isArray(out.type) && !out.type.includes('null')) out.type = [...out.type, 'null'];
    if (Array.isArray(out.enum) && !out.enum.includes(null)) out.enum = [...out.enum, null];
    if (!out.type && (out.allOf || out.oneOf || out.anyOf || out.$ref)) {
      const inner = { ...out };
      return { anyOf: [inner, { type: 'null' }] };
    }
  }
  return out;
}

export class Contract {
  static async load(server) {
    const r = await api(server, 'GET', '/api/v1/openapi.json', { check: false });
    assert.equal(r.status, 200, r.text);
    const doc = r.json;
    // validate() checks the document against the OpenAPI schema and resolves it (it mutates its input)
    await SwaggerParser.validate(structuredClone(doc));
    const deref = await SwaggerParser.dereference(structuredClone(doc));
    return new Contract(doc, deref);
  }
  constructor(doc, deref) {
    this.doc = doc;
    this.deref = deref;
    this.ajv = new Ajv({ strict: false, allErrors: true });
    addFormats(this.ajv);
    // OpenAPI's own formats
    this.ajv.addFormat('int32', { type: 'number', validate: (n) => Number.isInteger(n) && n >= -(2 ** 31) && n < 2 ** 31 });
    this.ajv.addFormat('int64', { type: 'number', validate: (n) => Number.isInteger(n) });
    for (const f of ['float', 'double']) this.ajv.addFormat(f, { type: 'number', validate: () => true });
    for (const f of ['byte', 'binary', 'password']) this.ajv.addFormat(f, () => true);
    this.cache = new Map();
    this.checked = []; // "METHOD template status" checked
    this.basePaths = [''];
    // servers: [{url: "/api/v1"}] means the paths are relative to /api/v1
    for (const sv of deref.servers || []) {
      try {
        const p = new URL(sv.url, 'http://x').pathname.replace(/\/$/, '');
        if (p && !this.basePaths.includes(p)) this.basePaths.push(p);
      } catch {
        /* ignore */
      }
    }
    this.templates = Object.keys(deref.paths).map((t) => ({
      t,
      segs: t.split('/'),
    }));
  }
  /** The document's path template matching a concrete path (query removed), or undefined. */
  template(pathname) {
    const p = pathname.split('?')[0];
    const candidates = [];
    for (const base of this.basePaths) {
      if (base && !p.startsWith(base + '/')) continue;
      const rel = p.slice(base.length).split('/');
      for (const { t, segs } of this.templates) {
        if (segs.length !== rel.length) continue;
        let score = 0;
        let ok = true;
        for (let i = 0; i < segs.length; i++) {
          if (/^\{.+\}$/.test(segs[i])) continue;
          if (segs[i] !== rel[i]) {
            ok = false;
            break;
          }
          score++;
        }
        if (ok) candidates.push({ t, score });
      }
    }
    candidates.sort((a, b) => b.score - a.score);
    return candidates.length ? candidates[0].t : undefined;
  }
  /** The JSON response schema of template+method+status (falls back to "4XX"/"default"), or undefined. */
  schema(template, method, status) {
    const op = this.deref.paths[template]?.[method.toLowerCase()];
    if (!op) return undefined;
    const responses = op.responses || {};
    const resp = responses[String(status)] || responses[`${String(status)[0]}XX`] || responses.default;
    if (!resp) return null; // documented operation, undocumented status
    const content = resp.content || {};
    const media = content['application/json'] || Object.entries(content).find(([k]) => k.includes('json'))?.[1];
    return media?.schema;
  }
  /**
   * Checks one JSON answer. strict: the path, operation and status must be documented (used by the
   * OpenAPI test); otherwise undocumented ones are skipped.
   */
  check(method, pathname, status, body, { strict = false } = {}) {
    const t = this.template(pathname);
    if (!t) {
      if (strict) assert.fail(`${pathname} is not in the OpenAPI document`);
      return false;
    }
    const s = this.schema(t, method, status);
    if (s === undefined) {
      if (strict) assert.fail(`${method} ${t} is not in the OpenAPI document`);
      return false;
    }
    if (s === null) {
      if (strict) assert.fail(`${method} ${t} does not document status ${status}`);
      return false;
    }
    const key = `${method} ${t} ${status}`;
    let validate = this.cache.get(key);
    if (!validate) {
      validate = this.ajv.compile(toJsonSchema(s));
      this.cache.set(key, validate);
    }
    const ok = validate(body);
    assert.ok(
      ok,
      `${key}: the answer does not match the OpenAPI schema: ${this.ajv.errorsText(validate.errors)}\n${JSON.stringify(body).slice(0, 1500)}`,
    );
    this.checked.push(key);
    return true;
  }
}

// ---------------------------------------------------------------- the CLI

/** `uavcover ARGS`: {code, stdout, stderr}. */
export function runCli(args, timeoutMs = 120000) {
  const r = spawnSync(CLI, args, { encoding: 'utf8', timeout: timeoutMs });
  return { code: r.status, signal: r.signal, stdout: r.stdout, stderr: r.stderr };
}

/**
 * Turns on the schema check of every JSON answer api() gets from `server`. When the document itself
 * is invalid the checks stay off (openapi.test.mjs reports that) so the other suites still run.
 */
export async function enableSchemaChecks(server) {
  try {
    await server.contract();
  } catch (e) {
    console.error(`schema checks off: ${e.message}`);
  }
}

/** A stand-in for `it` that names the backend (tests are generated once per backend). */
export function eachBackend(describe, body) {
  for (const backend of backends()) describe(backend, () => body(backend));
}
