// A minimal ZIP writer (STORE only, no compression): local headers, the data, a central directory
// and the end record (PKWARE APPNOTE 4.3). Enough to bundle a plan's exports into one download.

let table: Uint32Array | null = null;

/** CRC-32 (IEEE 802.3, reflected, polynomial 0xEDB88320) of the bytes. */
export function crc32(data: Uint8Array): number {
  if (!table) {
    table = new Uint32Array(256);
    for (let n = 0; n < 256; n++) {
      let c = n;
      for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
      table[n] = c >>> 0;
    }
  }
  let crc = 0xffffffff;
  for (let i = 0; i < data.length; i++) crc = table[(crc ^ data[i]) & 0xff] ^ (crc >>> 8);
  return (crc ^ 0xffffffff) >>> 0;
}

export interface ZipEntry {
  name: string;
  data: Uint8Array;
}

/** DOS date and time of a Date (local time, as zip tools show it). */
function dosDateTime(d: Date): [number, number] {
  const year = Math.max(1980, Math.min(2107, d.getFullYear()));
  const date = ((year - 1980) << 9) | ((d.getMonth() + 1) << 5) | d.getDate();
  const time = (d.getHours() << 11) | (d.getMinutes() << 5) | Math.floor(d.getSeconds() / 2);
  return [date, time];
}

/**
 * The zip archive holding the entries, stored uncompressed. Names are UTF-8 (flag bit 11); a name
 * may not repeat, be empty or exceed 65535 bytes, and the archive stays under 4 GiB (no ZIP64).
 */
export function zipStore(entries: ZipEntry[], when: Date = new Date()): Uint8Array {
  const enc = new TextEncoder();
  const [date, time] = dosDateTime(when);
  const seen = new Set<string>();
  const names = entries.map((e) => {
    if (!e.name || seen.has(e.name)) throw new Error(`zip: empty or repeated name "${e.name}"`);
    seen.add(e.name);
    const n = enc.encode(e.name);
    if (n.length > 0xffff) throw new Error(`zip: name too long "${e.name.slice(0, 40)}..."`);
    return n;
  });
  let size = 22;
  entries.forEach((e, i) => (size += 30 + names[i].length + e.data.length + 46 + names[i].length));
  if (size > 0xffffffff || entries.length > 0xffff) throw new Error('zip: archive too large');
  const out = new Uint8Array(size);
  const view = new DataView(out.buffer);
  let p = 0;
  const u16 = (v: number) => {
    view.setUint16(p, v, true);
    p += 2;
  };
  const u32 = (v: number) => {
    view.setUint32(p, v >>> 0, true);
    p += 4;
  };
  const offsets: number[] = [];
  const crcs: number[] = [];
  entries.forEach((e, i) => {
    offsets.push(p);
    const crc = crc32(e.data);
    crcs.push(crc);
    u32(0x04034b50); // local file header
    u16(20); // version needed: 2.0
    u16(0x0800); // flags: UTF-8 names
    u16(0); // method: stored
    u16(time);
    u16(date);
    u32(crc);
    u32(e.data.length);
    u32(e.data.length);
    u16(names[i].length);
    u16(0); // extra length
    out.set(names[i], p);
    p += names[i].length;
    out.set(e.data, p);
    p += e.data.length;
  });
  const cdStart = p;
  entries.forEach((e, i) => {
    u32(0x02014b50); // central directory header
    u16(0x0314); // made by: 2.0, Unix
    u16(20);
    u16(0x0800);
    u16(0);
    u16(time);
    u16(date);
    u32(crcs[i]);
    u32(e.data.length);
    u32(e.data.length);
    u16(names[i].length);
    u16(0); // extra
    u16(0); // comment
    u16(0); // disk
    u16(0); // internal attributes
    u32((0o100644 << 16) >>> 0); // external attributes: a regular file, rw-r--r--
    u32(offsets[i]);
    out.set(names[i], p);
    p += names[i].length;
  });
  const cdSize = p - cdStart;
  u32(0x06054b50); // end of central directory
  u16(0);
  u16(0);
  u16(entries.length);
  u16(entries.length);
  u32(cdSize);
  u32(cdStart);
  u16(0); // comment length
  return out;
}
