#!/usr/bin/env node
// Independent MAVLink vehicle for tests/mavlink, built on node-mavlink: receives one mission upload over
// UDP (or TCP) on 127.0.0.1 and prints what it got.
// Usage: node vehicle.js [sequential|reverse|fly|all] [sysid] [udp|tcp]
//   prints {"port": N} once bound, then, after acking the upload, {"items": [...]} and exits 0.
//   Fence and rally uploads (MAV_MISSION_TYPE_FENCE 1, _RALLY 2; issue 31) are answered with their own
//   mission type, kept apart from the mission and printed as {"fence": [...]} or {"rally": [...]}.
//   "all": stays after the mission until a fence and a rally upload came too, then exits 0.
//   "tcp": listens for one TCP connection instead (as SITL does on 5760) and writes every frame in two
//   pieces, the first 3 bytes and the rest in a later write, so the GCS reads frames split mid-header.
//   "reverse" requests the items last to first (out of order, to exercise the GCS).
//   "fly" (issue 12: an independent vehicle a flight follows in place of our simulator): keeps running
//   after the upload, sends HEARTBEAT (PX4 modes) every 200 ms, acks every COMMAND_LONG, arms on
//   MAV_CMD_COMPONENT_ARM_DISARM and, on MAV_CMD_MISSION_START, "flies" the items: every 40 ms the next
//   item's GLOBAL_POSITION_INT, MISSION_CURRENT and MISSION_ITEM_REACHED, then MISSION_CURRENT complete,
//   lands, disarms, prints {"flown": [seqs]} and exits 0.
//   Bounded: re-requests every 250 ms, gives up (exit 1) after 10 s (fly: 60 s).
'use strict'
const dgram = require('node:dgram')
const net = require('node:net')
const { MavLinkPacketSplitter, MavLinkPacketParser, MavLinkProtocolV2, minimal, common } = require('node-mavlink')

const order = process.argv[2] || 'sequential'
const sysid = Number(process.argv[3] || 1)
const transport = process.argv[4] || 'udp'
const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY }
const protocol = new MavLinkProtocolV2(sysid, 1)
const socket = dgram.createSocket('udp4')
const splitter = new MavLinkPacketSplitter()
const parser = splitter.pipe(new MavLinkPacketParser())

let peer = null
let txSeq = 0
let gcs = { system: 0, component: 0 }
let count = -1
let missionType = 0  // of the transfer in progress
const received = new Set()  // mission types uploaded
let items = new Map()
let pending = []  // seqs still to request, in request order
let timer = null

let stream = null  // tcp: the connected GCS
function send(message) {
  const bytes = protocol.serialize(message, txSeq++ & 0xff)
  if (transport === 'tcp') {
    if (!stream) return
    stream.write(bytes.subarray(0, 3))  // two writes, in order
    stream.write(bytes.subarray(3))
    return
  }
  socket.send(bytes, peer.port, peer.address)
}

function requestNext() {
  clearTimeout(timer)
  if (pending.length === 0) return
  const req = new common.MissionRequestInt()
  req.targetSystem = gcs.system
  req.targetComponent = gcs.component
  req.seq = pending[0]
  req.missionType = missionType
  send(req)
  timer = setTimeout(requestNext, 250)
}

function finish() {
  clearTimeout(timer)
  const ack = new common.MissionAck()
  ack.targetSystem = gcs.system
  ack.targetComponent = gcs.component
  ack.type = 0
  ack.missionType = missionType
  send(ack)
  const list = [...items.keys()].sort((a, b) => a - b).map((k) => items.get(k))
  const key = missionType === 1 ? 'fence' : missionType === 2 ? 'rally' : 'items'
  process.stdout.write(JSON.stringify({ [key]: list }) + '\n')
  received.add(missionType)
  count = -1
  if (order === 'fly') {
    if (missionType === 0) mission = list
    return
  }
  if (order === 'all' && !(received.has(0) && received.has(1) && received.has(2))) return
  if (order !== 'all' && missionType !== 0) return
  setTimeout(() => { shutdown(); process.exit(0) }, 50)
}

// ---- "fly" mode ----
let mission = []
let armed = false
let flying = false
let pos = { lat: 0, lon: 0, alt: 0 }
const flown = []
const PX4_AUTO = 4, PX4_READY = 1, PX4_MISSION = 4, PX4_LOITER = 3

function heartbeat() {
  if (!peer) return
  const hb = new minimal.Heartbeat()
  hb.type = 2  // quadrotor
  hb.autopilot = 12  // PX4
  hb.baseMode = 1 | (armed ? 128 : 0)  // custom mode enabled, safety armed
  hb.customMode = ((PX4_AUTO << 16) | ((flying ? PX4_MISSION : armed ? PX4_LOITER : PX4_READY) << 24)) >>> 0
  hb.systemStatus = armed ? 4 : 3  // active / standby
  hb.mavlinkVersion = 3
  send(hb)
}

function position() {
  const g = new common.GlobalPositionInt()
  g.timeBootMs = Date.now() % 4294967296
  g.lat = pos.lat
  g.lon = pos.lon
  g.alt = Math.round(pos.alt * 1000)
  g.relativeAlt = Math.round(pos.alt * 1000)
  g.hdg = 65535
  send(g)
}

function current(seq, state) {
  const c = new common.MissionCurrent()
  c.seq = seq
  c.total = mission.length
  c.missionState = state
  send(c)
}

function ack(command) {
  const a = new common.CommandAck()
  a.command = command
  a.result = 0
  a.targetSystem = gcs.system
  a.targetComponent = gcs.component
  send(a)
}

function fly(seq) {
  if (seq >= mission.length) {
    current(mission.length - 1, 5)  // MISSION_STATE_COMPLETE
    flying = false
    pos.alt = 0
    position()
    armed = false
    heartbeat()
    process.stdout.write(JSON.stringify({ flown }) + '\n')
    setTimeout(() => { shutdown(); process.exit(0) }, 1500)
    return
  }
  const it = mission[seq]
  if (it.command === 16 || it.command === 22 || it.command === 21) {
    pos = { lat: it.x, lon: it.y, alt: it.command === 21 ? 0 : it.z }
    position()
  }
  current(seq, 3)  // MISSION_STATE_ACTIVE
  const r = new common.MissionItemReached()
  r.seq = seq
  send(r)
  flown.push(seq)
  setTimeout(() => fly(seq + 1), 40)
}

function onCommand(c) {
  if (c.targetSystem !== sysid) return
  gcs = { system: c.header.sysid, component: c.header.compid }
  ack(c.command)
  if (c.command === 400) armed = c._param1 === 1  // MAV_CMD_COMPONENT_ARM_DISARM
  if (c.command === 300 && !flying && mission.length > 0) {  // MAV_CMD_MISSION_START
    armed = true
    flying = true
    fly(0)
  }
}

parser.on('data', (packet) => {
  const clazz = REGISTRY[packet.header.msgid]
  if (!clazz) return
  const data = packet.protocol.data(packet.payload, clazz)
  if (clazz === common.MissionCount && data.targetSystem === sysid) {
    gcs = { system: packet.header.sysid, component: packet.header.compid }
    count = data.count
    missionType = data.missionType || 0
    items = new Map()
    pending = [...Array(count).keys()]
    if (order === 'reverse') pending.reverse()
    requestNext()
  } else if (clazz === common.CommandLong && order === 'fly') {
    onCommand({ ...data, command: data.command, header: packet.header })
  } else if (clazz === common.MissionItemInt && data.targetSystem === sysid && count >= 0 &&
             (data.missionType || 0) === missionType) {
    if (pending.length > 0 && data.seq === pending[0]) {
      items.set(data.seq, data)
      pending.shift()
      if (pending.length === 0) finish()
      else requestNext()
    }
  }
})

let server = null
function shutdown() {
  if (server) {
    if (stream) stream.destroy()
    server.close()
  } else {
    socket.close()
  }
}
if (transport === 'tcp') {
  server = net.createServer((conn) => {
    conn.setNoDelay(true)
    stream = conn
    peer = { port: conn.remotePort, address: conn.remoteAddress }
    conn.on('data', (chunk) => splitter.write(chunk))
    conn.on('close', () => { stream = null })
  })
  server.listen(0, '127.0.0.1', () => {
    process.stdout.write(JSON.stringify({ port: server.address().port }) + '\n')
  })
} else {
  socket.on('message', (msg, rinfo) => {
    peer = rinfo
    splitter.write(msg)
  })
  socket.bind(0, '127.0.0.1', () => {
    process.stdout.write(JSON.stringify({ port: socket.address().port }) + '\n')
  })
}
if (order === 'fly') setInterval(heartbeat, 200)
setTimeout(() => {
  process.stderr.write(order === 'fly' ? 'vehicle.js: not flown within 60 s\n' : 'vehicle.js: no complete upload within 10 s\n')
  process.exit(1)
}, order === 'fly' ? 60000 : 10000)
