#!/usr/bin/env node
// Independent MAVLink vehicle for tests/mavlink, built on node-mavlink: receives one mission upload over
// UDP on 127.0.0.1 and prints what it got.
// Usage: node vehicle.js [sequential|reverse] [sysid]
//   prints {"port": N} once bound, then, after acking the upload, {"items": [...]} and exits 0.
//   "reverse" requests the items last to first (out of order, to exercise the GCS).
//   Bounded: re-requests every 250 ms, gives up (exit 1) after 10 s.
'use strict'
const dgram = require('node:dgram')
const { MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, minimal, common } = require('node-mavlink')

const order = process.argv[2] || 'sequential'
const sysid = Number(process.argv[3] || 1)
const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY }
const protocol = new MavLinkProtocolV2(sysid, 1)
const socket = dgram.createSocket('udp4')
const splitter = new MavLinkPacketSplitter()
const parser = splitter.pipe(new MavLinkPacketParser())

let peer = null
let txSeq = 0
let gcs = { system: 0, component: 0 }
let count = -1
let items = new Map()
let pending = []  // seqs still to request, in request order
let timer = null

function send(message) {
  socket.send(protocol.serialize(message, txSeq++ & 0xff), peer.port, peer.address)
}

function requestNext() {
  clearTimeout(timer)
  if (pending.length === 0) return
  const req = new common.MissionRequestInt()
  req.targetSystem = gcs.system
  req.targetComponent = gcs.component
  req.seq = pending[0]
  req.missionType = 0
  send(req)
  timer = setTimeout(requestNext, 250)
}

function finish() {
  clearTimeout(timer)
  const ack = new common.MissionAck()
  ack.targetSystem = gcs.system
  ack.targetComponent = gcs.component
  ack.type = 0
  ack.missionType = 0
  send(ack)
  const list = [...items.keys()].sort((a, b) => a - b).map((k) => items.get(k))
  process.stdout.write(JSON.stringify({ items: list }) + '\n')
  setTimeout(() => { socket.close(); process.exit(0) }, 50)
}

parser.on('data', (packet) => {
  const clazz = REGISTRY[packet.header.msgid]
  if (!clazz) return
  const data = packet.protocol.data(packet.payload, clazz)
  if (clazz === common.MissionCount && data.targetSystem === sysid) {
    gcs = { system: packet.header.sysid, component: packet.header.compid }
    count = data.count
    items = new Map()
    pending = [...Array(count).keys()]
    if (order === 'reverse') pending.reverse()
    requestNext()
  } else if (clazz === common.MissionItemInt && data.targetSystem === sysid && count >= 0) {
    if (pending.length > 0 && data.seq === pending[0]) {
      items.set(data.seq, data)
      pending.shift()
      if (pending.length === 0) finish()
      else requestNext()
    }
  }
})

socket.on('message', (msg, rinfo) => {
  peer = rinfo
  splitter.write(msg)
})
socket.bind(0, '127.0.0.1', () => {
  process.stdout.write(JSON.stringify({ port: socket.address().port }) + '\n')
})
setTimeout(() => { process.stderr.write('vehicle.js: no complete upload within 10 s\n'); process.exit(1) }, 10000)
