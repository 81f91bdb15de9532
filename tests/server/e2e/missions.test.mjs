// Missions: create, read, revise (old revisions stay readable), list with paging and filters, delete.
import { describe, it, before, after } from 'node:test';
import assert from 'node:assert/strict';
import {
  api,
  assertError,
  createMission,
  eachBackend,
  enableSchemaChecks,
  freshDb,
  oliveGrove,
  readJson,
  rectangle,
  startServer,
  EXAMPLES,
} from './harness.mjs';
import path from 'node:path';

async function listAll(server, query) {
  const items = [];
  let cursor = null;
  let pages = 0;
  for (;;) {
    const q = new URLSearchParams(query);
    if (cursor !== null) q.set('cursor', String(cursor));
    const r = await api(server, 'GET', `/api/v1/missions?${q}`);
    assert.equal(r.status, 200, r.text);
    assert.ok(Array.isArray(r.json.items));
    assert.ok('next_cursor' in r.json, 'next_cursor missing');
    items.push(...r.json.items);
    pages++;
    assert.ok(pages < 100, 'paging does not end');
    if (r.json.next_cursor === null) break;
    cursor = r.json.next_cursor;
  }
  return { items, pages };
}

eachBackend(describe, (backend) => {
  let db;
  let server;
  before(async () => {
    db = freshDb(backend);
    server = await startServer({ db });
    await enableSchemaChecks(server);
  });
  after(async () => {
    await server?.stop();
  });

  it('seeds the example missions once', async () => {
    const { items } = await listAll(server, { limit: '1000' });
    const names = items.map((m) => m.name);
    assert.ok(names.includes(oliveGrove().name), `seeded: ${names}`);
    assert.equal(items.length, 2, `the two files of examples/: ${names}`);
    // a restart on the same database does not seed again
    await server.stop();
    server = await startServer({ db });
    await enableSchemaChecks(server);
    const again = await listAll(server, { limit: '1000' });
    assert.deepEqual(
      again.items.map((m) => m.id),
      items.map((m) => m.id),
    );
  });

  it('creates, revises, reads old revisions and deletes a mission', async () => {
    const doc = oliveGrove();
    doc.name = 'lifecycle grove';
    const post = await api(server, 'POST', '/api/v1/missions', { body: doc });
    assert.equal(post.status, 201, post.text);
    const id = post.json.id;
    assert.ok(Number.isInteger(id) && id > 0);
    assert.equal(post.json.revision, 1);
    assert.equal(post.headers.get('location'), `/api/v1/missions/${id}`);
    assert.ok(post.headers.get('x-request-id'), 'X-Request-Id');

    const get1 = await api(server, 'GET', `/api/v1/missions/${id}`);
    assert.equal(get1.status, 200, get1.text);
    assert.equal(get1.json.id, id);
    assert.equal(get1.json.name, 'lifecycle grove');
    assert.equal(get1.json.revision, 1);
    assert.equal(get1.json.latest_revision, 1);
    assert.equal(get1.json.source.name, 'lifecycle grove');
    assert.equal(get1.json.mission.name, 'lifecycle grove');
    assert.equal(get1.json.mission.uavs.length, 3);
    const [minLon, minLat, maxLon, maxLat] = get1.json.bbox;
    assert.ok(Math.abs(minLon - 22.899) < 1e-6 && Math.abs(maxLon - 22.9145) < 1e-6, `bbox ${get1.json.bbox}`);
    assert.ok(Math.abs(minLat - 40.6) < 1e-6 && Math.abs(maxLat - 40.6085) < 1e-6, `bbox ${get1.json.bbox}`);
    assert.match(get1.json.created, /^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d(\.\d+)?Z$/);

    const doc2 = { ...doc, name: 'lifecycle grove v2', uavs: doc.uavs.slice(0, 2) };
    const put = await api(server, 'PUT', `/api/v1/missions/${id}`, { body: doc2 });
    assert.equal(put.status, 200, put.text);
    assert.deepEqual({ id: put.json.id, revision: put.json.revision }, { id, revision: 2 });

    const get2 = await api(server, 'GET', `/api/v1/missions/${id}`);
    assert.equal(get2.json.revision, 2);
    assert.equal(get2.json.latest_revision, 2);
    assert.equal(get2.json.name, 'lifecycle grove v2');
    assert.equal(get2.json.mission.uavs.length, 2);

    const old = await api(server, 'GET', `/api/v1/missions/${id}/revisions/1`);
    assert.equal(old.status, 200, old.text);
    assert.equal(old.json.revision, 1);
    assert.equal(old.json.latest_revision, 2);
    assert.equal(old.json.name, 'lifecycle grove');
    assert.equal(old.json.mission.uavs.length, 3);
    assert.deepEqual(old.json.source, get1.json.source);
    const rev2 = await api(server, 'GET', `/api/v1/missions/${id}/revisions/2`);
    assert.equal(rev2.json.name, 'lifecycle grove v2');
    assertError(await api(server, 'GET', `/api/v1/missions/${id}/revisions/3`), 404);

    // an invalid revision is refused and changes nothing
    const bad = await api(server, 'PUT', `/api/v1/missions/${id}`, { body: { ...doc, uavs: [] } });
    assertError(bad, 422);
    assert.equal((await api(server, 'GET', `/api/v1/missions/${id}`)).json.revision, 2);

    const del = await api(server, 'DELETE', `/api/v1/missions/${id}`);
    assert.equal(del.status, 204, del.text);
    assert.equal(del.text, '');
    assertError(await api(server, 'GET', `/api/v1/missions/${id}`), 404);
    assertError(await api(server, 'GET', `/api/v1/missions/${id}/revisions/1`), 404);
    assertError(await api(server, 'DELETE', `/api/v1/missions/${id}`), 404);
    assertError(await api(server, 'PUT', `/api/v1/missions/${id}`, { body: doc }), 404);
  });

  it('accepts the mCPP input format', async () => {
    const mcpp = readJson(path.join(EXAMPLES, 'mcpp-darp-input.json'));
    const id = await createMission(server, mcpp);
    const r = await api(server, 'GET', `/api/v1/missions/${id}`);
    assert.equal(r.status, 200, r.text);
    assert.deepEqual(r.json.source, mcpp);
    assert.ok(Array.isArray(r.json.mission.uavs) && r.json.mission.uavs.length > 0);
  });

  it('lists missions in pages with a cursor, filters by name and bounding box', async () => {
    const ids = [];
    for (let i = 0; i < 7; i++) {
      const doc = i % 2 ? rectangle() : oliveGrove();
      doc.name = `Paging-${i % 2 ? 'Rect' : 'Grove'} ${i}`;
      ids.push(await createMission(server, doc));
    }
    const { items, pages } = await listAll(server, { name: 'paging-', limit: '2' });
    assert.equal(pages, 4);
    assert.deepEqual(
      items.map((m) => m.id),
      ids,
      'ascending ids, each once',
    );
    for (const m of items) {
      for (const k of ['bbox', 'created', 'id', 'name', 'revision', 'updated']) assert.ok(k in m, `${k} in ${JSON.stringify(m)}`);
      assert.ok(!('mission' in m) && !('source' in m), 'a summary, not the document');
    }
    // case-insensitive substring
    const rect = await listAll(server, { name: 'PAGING-RECT', limit: '50' });
    assert.deepEqual(
      rect.items.map((m) => m.name),
      ['Paging-Rect 1', 'Paging-Rect 3', 'Paging-Rect 5'],
    );
    // plain text, no wildcards
    const none = await listAll(server, { name: 'paging-%', limit: '50' });
    assert.equal(none.items.length, 0);
    const under = await listAll(server, { name: 'paging_', limit: '50' });
    assert.equal(under.items.length, 0);
    // the rectangle lies near 9.15E 45.39N, the grove near 22.9E 40.6N
    const italy = await listAll(server, { name: 'paging', bbox: '9.0,45.0,9.5,45.5' });
    assert.deepEqual(
      italy.items.map((m) => m.name),
      ['Paging-Rect 1', 'Paging-Rect 3', 'Paging-Rect 5'],
    );
    const greece = await listAll(server, { name: 'paging', bbox: '22.905,40.605,22.906,40.606' });
    assert.deepEqual(
      greece.items.map((m) => m.name),
      ['Paging-Grove 0', 'Paging-Grove 2', 'Paging-Grove 4', 'Paging-Grove 6'],
    );
    const ocean = await listAll(server, { name: 'paging', bbox: '-30,-10,-29,-9' });
    assert.equal(ocean.items.length, 0);
    // a full page without a filter holds the seeded missions too
    const first = await api(server, 'GET', '/api/v1/missions?limit=1000');
    assert.ok(first.json.items.length >= 9);
    assert.equal(first.json.next_cursor, null);
    // a deleted mission leaves the list
    assert.equal((await api(server, 'DELETE', `/api/v1/missions/${ids[1]}`)).status, 204);
    const remaining = await listAll(server, { name: 'paging-rect' });
    assert.deepEqual(
      remaining.items.map((m) => m.id),
      [ids[3], ids[5]],
    );
  });
});
