#!/usr/bin/env node
// Independent MAVLink peer for tests/mavlink: decodes frames with node-mavlink.
// Input (stdin): hex text, frames back to back (whitespace and newlines ignored).
// Output (stdout): one JSON object per valid packet, then {"summary": {...}} with the splitter's counts.
'use strict'
const { Readable } = require('node:stream')
const { MavLinkPacketSplitter, MavLinkPacketParser, minimal, common } = require('node-mavlink')

const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY }

let text = ''
process.stdin.setEncoding('utf8')
process.stdin.on('data', (chunk) => { text += chunk })
process.stdin.on('end', () => {
  const bytes = Buffer.from(text.replace(/\s+/g, ''), 'hex')
  const splitter = new MavLinkPacketSplitter()
  const reader = Readable.from([bytes]).pipe(splitter).pipe(new MavLinkPacketParser())
  reader.on('data', (packet) => {
    const clazz = REGISTRY[packet.header.msgid]
    const out = {
      magic: packet.header.magic,
      msgid: packet.header.msgid,
      seq: packet.header.seq,
      sysid: packet.header.sysid,
      compid: packet.header.compid,
      payloadLength: packet.header.payloadLength,
      crc: packet.crc,
      name: clazz ? clazz.MSG_NAME : null,
      fields: clazz ? packet.protocol.data(packet.payload, clazz) : null,
    }
    process.stdout.write(JSON.stringify(out) + '\n')
  })
  reader.on('end', () => {
    process.stdout.write(JSON.stringify({
      summary: {
        valid: splitter.validPackages,
        invalid: splitter.invalidPackages,
        unknown: splitter.unknownPackagesCount,
      },
    }) + '\n')
  })
})
