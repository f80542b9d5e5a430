#!/usr/bin/env node
// Independent check of can/gvs.dbc with the npm package candied:
// 1. the DBC loads with no parse errors; 2. candied decodes the frames the
// C++ codec encodes (gvs_can_examples --json) to the values the codec was
// given, for every signal of the DBC.
// Usage: node check_dbc_candied.cjs GVS_DBC GVS_CAN_EXAMPLES_BINARY
// Needs `npm ci --prefix tests/can/candied` first (installs nothing itself).
'use strict';
const fs = require('fs');
const path = require('path');
const { execFileSync } = require('child_process');

const [dbcPath, examplesBin] = process.argv.slice(2);
if (!dbcPath || !examplesBin) {
  console.log('usage: check_dbc_candied.cjs GVS_DBC GVS_CAN_EXAMPLES_BINARY');
  process.exit(2);
}
let candied;
try {
  candied = require(path.join(__dirname, 'node_modules', 'candied'));
} catch (e) {
  console.log(`FAIL: candied is not installed (${e.message.split('\n')[0]}); run: npm ci --prefix tests/can/candied`);
  process.exit(1);
}
const dbc = new candied.Dbc();
const data = dbc.load(fs.readFileSync(dbcPath, 'ascii'));
let failures = 0;
if (dbc.errors && dbc.errors.size > 0) {
  for (const [line, errs] of dbc.errors) console.log(`FAIL: candied: line ${line}: ${errs.map(String).join('; ')}`);
  failures++;
}
const boMessages = fs.readFileSync(dbcPath, 'ascii').split('\n').filter((l) => l.startsWith('BO_ ')).length;
if (data.messages.size !== boMessages) {
  console.log(`FAIL: the DBC has ${boMessages} BO_ lines, candied loaded ${data.messages.size} messages`);
  failures++;
}
console.log(`candied loaded ${dbcPath}: ${data.messages.size} messages, ${dbc.errors ? dbc.errors.size : 0} errors`);

const can = new candied.Can();
can.database = data;
const covered = new Set();
const cases = execFileSync(examplesBin, ['--json'], { encoding: 'utf8' }).split('\n').filter((l) => l.trim()).map(JSON.parse);
for (const c of cases) {
  const bytes = Buffer.from(c.data, 'hex');
  const bound = can.decode(can.createFrame(c.id, Array.from(bytes)));
  if (!bound || bound.name !== c.message) {
    console.log(`FAIL: ID ${c.id} decodes as ${bound ? bound.name : 'nothing'}, codec says ${c.message}`);
    failures++;
    continue;
  }
  const names = [...bound.boundSignals.keys()].sort();
  const want = Object.keys(c.expect).sort();
  if (JSON.stringify(names) !== JSON.stringify(want)) {
    console.log(`FAIL: ${c.message}: candied signals ${names} differ from the codec's ${want}`);
    failures++;
  }
  const msg = data.messages.get(c.message);
  for (const [name, expected] of Object.entries(c.expect)) {
    const sig = bound.boundSignals.get(name);
    const def = msg.signals.get(name);
    if (!sig || !def) continue;
    const value = sig.rawValue * def.factor + def.offset;
    covered.add(`${c.message}.${name}`);
    if (Math.abs(value - expected) > def.factor / 2 + 1e-9) {
      console.log(`FAIL: ${c.message}.${name}: candied decodes ${value}, codec encoded ${expected} (frame ${c.data})`);
      failures++;
    }
  }
}
let all = 0;
for (const [mname, m] of data.messages) {
  for (const sname of m.signals.keys()) {
    all++;
    if (!covered.has(`${mname}.${sname}`)) {
      console.log(`FAIL: ${mname}.${sname} never checked`);
      failures++;
    }
  }
}
console.log(`${cases.length} frames, ${covered.size} of ${all} signals cross-checked, ${failures} failures`);
process.exit(failures ? 1 : 0);
