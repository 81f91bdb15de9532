// zip.ts: a STORE-only zip writer. Its output is read back by Python's zipfile (which checks every
// CRC-32) and by `unzip -t` when present.
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { test } from 'node:test';
import { crc32, zipStore } from '../../src/zip.ts';

const enc = new TextEncoder();

test('crc32 of known strings', () => {
  assert.equal(crc32(enc.encode('')), 0);
  assert.equal(crc32(enc.encode('123456789')), 0xcbf43926);
  assert.equal(crc32(enc.encode('The quick brown fox jumps over the lazy dog')), 0x414fa339);
});

test('a zip that Python reads back byte for byte', () => {
  const big = new Uint8Array(200000);
  for (let i = 0; i < big.length; i++) big[i] = (i * 7919) & 0xff;
  const entries = [
    { name: 'uav1.plan', data: enc.encode('{"fileType": "Plan"}\n') },
    { name: 'empty.txt', data: new Uint8Array(0) },
    { name: 'dir/ünïcode.kml', data: enc.encode('<kml/>') },
    { name: 'big.bin', data: big },
  ];
  const dir = mkdtempSync(join(tmpdir(), 'zip-test-'));
  try {
    const path = join(dir, 'out.zip');
    writeFileSync(path, zipStore(entries, new Date(2026, 10, 26, 12, 30, 10)));
    const py = `
import json, sys, zipfile
z = zipfile.ZipFile(sys.argv[1])
bad = z.testzip()
out = {"bad": bad, "files": [[i.filename, i.file_size, i.compress_type, list(i.date_time)] for i in z.infolist()]}
out["data"] = {i.filename: z.read(i.filename).hex() if i.file_size < 100 else len(z.read(i.filename)) for i in z.infolist()}
print(json.dumps(out))`;
    const res = JSON.parse(execFileSync('python3', ['-c', py, path], { encoding: 'utf8' }));
    assert.equal(res.bad, null);
    assert.deepEqual(
      res.files.map((f) => [f[0], f[1], f[2]]),
      entries.map((e) => [e.name, e.data.length, 0]),
    );
    assert.deepEqual(res.files[0][3], [2026, 11, 26, 12, 30, 10]);
    assert.equal(res.data['uav1.plan'], Buffer.from('{"fileType": "Plan"}\n').toString('hex'));
    assert.equal(res.data['big.bin'], big.length);
    let unzip = null;
    try {
      unzip = execFileSync('unzip', ['-t', path], { encoding: 'utf8' });
    } catch (e) {
      if (e.code !== 'ENOENT') throw e;
    }
    if (unzip !== null) assert.match(unzip, /No errors detected/);
    assert.ok(readFileSync(path).length > big.length);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});

test('repeated or empty names are refused', () => {
  assert.throws(() => zipStore([{ name: 'a', data: new Uint8Array(1) }, { name: 'a', data: new Uint8Array(1) }]), /repeated/);
  assert.throws(() => zipStore([{ name: '', data: new Uint8Array(1) }]), /empty/);
});
