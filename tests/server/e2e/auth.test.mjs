// The token rule: off loopback the server needs --token-file, and then every request a bearer token
// (the health check stays open). No CORS headers unless configured. (The rule does not depend on the
// database: SQLite only.)
import { describe, it, before, after } from 'node:test';
import assert from 'node:assert/strict';
import fs from 'node:fs';
import path from 'node:path';
import { api, assertError, freshDb, rectangle, runServe, startServer, tempDir, WebSocket } from './harness.mjs';

describe('token rule', () => {
  it('refuses to listen on 0.0.0.0 without --token-file', () => {
    const db = freshDb('sqlite');
    const r = runServe(['--listen', '0.0.0.0:0', '--db', db.url]);
    assert.notEqual(r.code, 0, `exit code ${r.code}, stdout ${r.stdout}`);
    assert.equal(r.signal, null, 'no crash');
    assert.match(r.stdout + r.stderr, /--token-file/);
    assert.doesNotMatch(r.stdout, /serving on/);
  });

  it('refuses a token file that does not exist or is empty', () => {
    const dir = tempDir();
    const db = freshDb('sqlite');
    const missing = runServe(['--listen', '0.0.0.0:0', '--db', db.url, '--token-file', path.join(dir, 'nope')]);
    assert.notEqual(missing.code, 0);
    assert.equal(missing.signal, null);
    const empty = path.join(dir, 'empty');
    fs.writeFileSync(empty, '\n');
    const r = runServe(['--listen', '0.0.0.0:0', '--db', db.url, '--token-file', empty]);
    assert.notEqual(r.code, 0, 'an empty token would let everyone in');
    assert.equal(r.signal, null);
  });

  describe('on 0.0.0.0 with --token-file', () => {
    const token = 'e2e-Token-0123456789abcdef';
    let server;
    before(async () => {
      const dir = tempDir();
      const file = path.join(dir, 'token');
      fs.writeFileSync(file, `${token}\n`);
      server = await startServer({ db: freshDb('sqlite'), listen: '0.0.0.0:0', args: ['--token-file', file] });
      // reach it over loopback
      server.url = server.url.replace('//0.0.0.0:', '//127.0.0.1:');
    });
    after(async () => {
      await server?.stop();
    });

    it('answers 401 without a token or with a wrong one', async () => {
      for (const t of [null, 'wrong', `${token}x`, token.slice(0, -1), token.toUpperCase(), '']) {
        const r = await api(server, 'GET', '/api/v1/missions', { token: t });
        assertError(r, 401);
      }
      for (const h of [`Basic ${token}`, `bearer${token}`, token]) {
        const r = await api(server, 'GET', '/api/v1/missions', { token: null, headers: { authorization: h } });
        assertError(r, 401);
      }
      // writes too
      assertError(await api(server, 'POST', '/api/v1/missions', { token: null, body: rectangle() }), 401);
      assertError(await api(server, 'GET', '/api/v1/openapi.json', { token: null }), 401);
      assertError(await api(server, 'GET', '/metrics', { token: null }), 401);
    });

    it('answers 200 with the bearer token; /healthz is open', async () => {
      const r = await api(server, 'GET', '/api/v1/missions', { token });
      assert.equal(r.status, 200, r.text);
      const post = await api(server, 'POST', '/api/v1/missions', { token, body: rectangle() });
      assert.equal(post.status, 201, post.text);
      const h = await api(server, 'GET', '/healthz', { token: null });
      assert.equal(h.status, 200, h.text);
      assert.equal(h.json.status, 'ok');
    });

    it('refuses a WebSocket without the token and accepts one with it', async () => {
      const ws = new WebSocket(`${server.wsUrl}/api/v1/events`);
      const status = await new Promise((resolve) => {
        ws.once('unexpected-response', (_req, res) => resolve(res.statusCode));
        ws.once('open', () => resolve('open'));
        ws.once('error', () => resolve('error'));
      });
      assert.equal(status, 401);
      const ok = new WebSocket(`${server.wsUrl}/api/v1/events`, { headers: { authorization: `Bearer ${token}` } });
      await new Promise((resolve, reject) => {
        ok.once('open', resolve);
        ok.once('error', reject);
      });
      ok.close();
    });

    it('sends no CORS headers when none are configured, and refuses a foreign origin (403)', async () => {
      const r = await api(server, 'GET', '/api/v1/missions', { token, headers: { origin: 'http://evil.example' } });
      assertError(r, 403, 'origin');
      assert.equal(r.headers.get('access-control-allow-origin'), null);
      const plain = await api(server, 'GET', '/api/v1/missions', { token });
      assert.equal(plain.status, 200, plain.text);
      assert.equal(plain.headers.get('access-control-allow-origin'), null);
    });
  });

  it('needs no token on loopback', async () => {
    const server = await startServer({ db: freshDb('sqlite') });
    try {
      const r = await api(server, 'GET', '/api/v1/missions');
      assert.equal(r.status, 200, r.text);
      assert.equal((await api(server, 'GET', '/readyz')).status, 200);
    } finally {
      await server.stop();
    }
  });
});
