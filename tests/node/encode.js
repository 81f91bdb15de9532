#!/usr/bin/env node
// Independent MAVLink peer for tests/mavlink: encodes frames with node-mavlink.
// Input (stdin): a JSON array of {"message": "MissionItemInt", "sysid": 1, "compid": 1, "seq": 0,
//   "fields": {"seq": 3, "x": 473977420, ...}} (node-mavlink class names, camelCase field names).
// Output (stdout): one MAVLink 2 frame per line, as hex.
'use strict'
const { MavLinkProtocolV2, minimal, common } = require('node-mavlink')

const CLASSES = { ...minimal, ...common }

let text = ''
process.stdin.setEncoding('utf8')
process.stdin.on('data', (chunk) => { text += chunk })
process.stdin.on('end', () => {
  for (const spec of JSON.parse(text)) {
    const Clazz = CLASSES[spec.message]
    if (typeof Clazz !== 'function' || Clazz.MSG_ID === undefined) {
      throw new Error(`unknown message class ${spec.message}`)
    }
    const msg = new Clazz()
    for (const [key, value] of Object.entries(spec.fields || {})) msg[key] = value
    const protocol = new MavLinkProtocolV2(spec.sysid, spec.compid)
    process.stdout.write(protocol.serialize(msg, spec.seq).toString('hex') + '\n')
  }
})
