// The bridge's CDR against an independent serializer: for every ROS 2 type
// the bridge publishes, the bytes it put on DDS (ros2_cdr_dump) are read by
// @foxglove/rosmsg2-serialization with the ROS 2 definitions, the values
// are checked against what the devices sent, and the same values written
// again by @foxglove/rosmsg2-serialization must give the same bytes.
//
// Definitions: ROS 2 Jazzy's from @foxglove/rosmsg-msgs-common where it has
// the type (everything but rmw_dds_common); else the bridge's own .msg files
// (drivers/ros2/msg) parsed by @foxglove/rosmsg. The bridge's .msg files are
// also held against @foxglove/rosmsg-msgs-common's field by field.
//
// usage: node cdr_check.mjs --modules DIR --msg DIR --dump PROGRAM
// Exit 0: passed, 1: failed.
import { execFileSync } from 'node:child_process';
import { readdirSync, readFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { join, resolve } from 'node:path';

const args = {};
for (let i = 2; i + 1 < process.argv.length; i += 2) args[process.argv[i].replace(/^--/, '')] = process.argv[i + 1];
const require = createRequire(join(resolve(args.modules), 'noop.js'));
const { parse } = require('@foxglove/rosmsg');
const { MessageReader, MessageWriter } = require('@foxglove/rosmsg2-serialization');
const { ros2jazzy } = require('@foxglove/rosmsg-msgs-common');

let failures = 0;
function check(ok, what, detail = '') {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}${detail ? ': ' + detail : ''}`);
  if (!ok) failures++;
  return ok;
}

// ---- The bridge's definitions -------------------------------------------------

const own = {};  // "pkg/Type" -> .msg text
for (const pkg of readdirSync(args.msg, { withFileTypes: true }).filter((e) => e.isDirectory())) {
  for (const f of readdirSync(join(args.msg, pkg.name)).filter((f) => f.endsWith('.msg'))) {
    own[`${pkg.name}/${f.slice(0, -4)}`] = readFileSync(join(args.msg, pkg.name, f), 'utf8');
  }
}

const kPrimitives = new Set(['bool', 'byte', 'char', 'int8', 'uint8', 'int16', 'uint16', 'int32', 'uint32',
  'int64', 'uint64', 'float32', 'float64', 'string', 'wstring']);

// The nested types a definition names ("Gid gid" inside rmw_dds_common).
function nested(type) {
  const pkg = type.split('/')[0];
  const out = [];
  for (const line of own[type].split('\n')) {
    const first = line.replace(/#.*/, '').trim().split(/\s+/)[0];
    const base = first.replace(/\[.*\]$/, '').replace(/<=\d+$/, '');
    if (!base || kPrimitives.has(base)) continue;
    out.push(base.includes('/') ? base : `${pkg}/${base}`);
  }
  return out.filter((t) => own[t]);
}

// One type with its dependencies, the way ROS 2 tools concatenate them.
function ownDefinitions(type) {
  const seen = new Set([type]);
  const todo = nested(type);
  let text = own[type];
  while (todo.length) {
    const t = todo.shift();
    if (seen.has(t)) continue;
    seen.add(t);
    text += `\n${'='.repeat(80)}\nMSG: ${t}\n${own[t]}`;
    todo.push(...nested(t));
  }
  return parse(text, { ros2: true });
}

const fieldsOf = (defs) =>
  defs
    .filter((f) => !f.isConstant)
    .map((f) => JSON.stringify([f.name, f.type, !!f.isArray, f.arrayLength ?? null, f.upperBound ?? null]));

for (const type of Object.keys(own).sort()) {
  const theirs = ros2jazzy[type];
  if (!theirs) continue;
  const mine = fieldsOf(ownDefinitions(type)[0].definitions);
  const want = fieldsOf(theirs.definitions);
  check(JSON.stringify(mine) === JSON.stringify(want), `${type}: our .msg has ROS 2 Jazzy's fields`,
        JSON.stringify(mine) === JSON.stringify(want) ? '' : `ours ${mine.join(' ')} / Jazzy ${want.join(' ')}`);
}

// ---- The bytes ------------------------------------------------------------------

function definitionsFor(rosName) {
  const key = rosName.replace('/msg/', '/');
  if (ros2jazzy[key]) return { defs: [ros2jazzy[key], ...Object.values(ros2jazzy)], from: 'rosmsg-msgs-common (Jazzy)' };
  return { defs: ownDefinitions(key), from: 'drivers/ros2/msg' };
}

function valueAt(msg, path) {
  let v = msg;
  for (const k of path.split('.')) v = v?.[/^\d+$/.test(k) ? Number(k) : k];
  return v;
}

function same(got, want) {
  if (want === 'NaN') return Number.isNaN(got);
  if (want === 'Infinity') return got === Infinity;
  if (want === '-Infinity') return got === -Infinity;
  if (typeof want === 'number' && typeof got === 'number') {
    return Math.abs(got - want) <= 1e-6 * Math.max(1, Math.abs(want));
  }
  if (typeof got === 'bigint') return got === BigInt(want);
  return got === want;
}

const dump = execFileSync(args.dump, { encoding: 'utf8', timeout: 120000 });
const samples = dump.trim().split('\n').map((l) => JSON.parse(l));
const types = new Set();
for (const s of samples) {
  const { defs, from } = definitionsFor(s.type);
  const what = `${s.topic} (${s.type}, definitions from ${from})`;
  const bytes = Buffer.from(s.cdr, 'hex');
  types.add(s.type);
  let msg;
  try {
    msg = new MessageReader(defs).readMessage(bytes);
  } catch (e) {
    check(false, `${what}: decodes`, String(e));
    continue;
  }
  for (const [path, want] of Object.entries(s.expect)) {
    const got = valueAt(msg, path);
    check(same(got, want), `${what}: ${path}`, same(got, want) ? '' : `got ${got}, want ${want}`);
  }
  // Cyclone DDS pads a sample to a multiple of 4 bytes and says how much in
  // the last two bits of the encapsulation options (DDS-XTypes 7.6.3.1.2);
  // rosmsg2-serialization does not pad. Only what the header announces is
  // taken off, and it must be zeros.
  const pad = bytes[3] & 3;
  const tail = bytes.subarray(bytes.length - pad);
  check(bytes[2] === 0 && (bytes[3] & ~3) === 0 && tail.every((b) => b === 0), `${what}: encapsulation options`,
        bytes.subarray(0, 4).toString('hex'));
  const core = Buffer.concat([bytes.subarray(0, 2), Buffer.from([0, 0]), bytes.subarray(4, bytes.length - pad)]);
  const again = Buffer.from(new MessageWriter(defs).writeMessage(msg));
  const firstDiff = again.findIndex((b, i) => b !== core[i]);
  check(again.equals(core), `${what}: ${core.length} bytes, the same as rosmsg2-serialization writes`,
        again.equals(core) ? '' : `lengths ${core.length}/${again.length}, first difference at byte ${firstDiff}`);
}
check(types.size >= 11, `every published type was checked (${[...types].sort().join(', ')})`);
console.log(failures ? `${failures} FAILED` : 'all passed');
process.exit(failures ? 1 : 0);
