// The workload of `quiver bench crdt` run against Yjs (Debian's node-yjs), for `quiver bench
// all`: replica A holds NODES maps of ATTRS doubles and makes UPDATES random writes in
// transactions of BATCH; replica B applies every update A emits. Prints one JSON line.
// Usage: node yjs_crdt.js NODES ATTRS UPDATES BATCH SEED   (NODE_PATH=/usr/share/nodejs)
'use strict';
const Y = require('yjs');

const [nodes, attrs, updates, batch, seed] = process.argv.slice(2).map(Number);
// mulberry32: a seeded generator, so that a run replays.
let state = seed >>> 0;
function random() {
  state = (state + 0x6d2b79f5) >>> 0;
  let t = state;
  t = Math.imul(t ^ (t >>> 15), t | 1);
  t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
  return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
}

const a = new Y.Doc();
const sent = [];
a.on('update', (u) => sent.push(u));
const world = a.getMap('nodes');
const maps = [];
a.transact(() => {
  for (let n = 0; n < nodes; ++n) {
    const m = new Y.Map();
    world.set('n' + n, m);
    for (let k = 0; k < attrs; ++k) m.set('a' + k, 0.0);
    maps.push(m);
  }
});
const setup = sent.length;

let t0 = process.hrtime.bigint();
for (let done = 0; done < updates; done += batch) {
  a.transact(() => {
    for (let i = 0; i < batch && done + i < updates; ++i)
      maps[Math.floor(random() * nodes)].set('a' + Math.floor(random() * attrs), random());
  });
}
const localS = Number(process.hrtime.bigint() - t0) / 1e9;

const b = new Y.Doc();
for (let i = 0; i < setup; ++i) Y.applyUpdate(b, sent[i]);
t0 = process.hrtime.bigint();
for (let i = setup; i < sent.length; ++i) Y.applyUpdate(b, sent[i]);
const remoteS = Number(process.hrtime.bigint() - t0) / 1e9;

let bytes = 0;
for (let i = setup; i < sent.length; ++i) bytes += sent[i].length;
const same = Buffer.compare(Buffer.from(Y.encodeStateVector(a)), Buffer.from(Y.encodeStateVector(b))) === 0 &&
  JSON.stringify(a.getMap('nodes').toJSON()) === JSON.stringify(b.getMap('nodes').toJSON());
console.log(JSON.stringify({
  impl: 'yjs', yjs_version: require('yjs/package.json').version, node_version: process.versions.node,
  nodes, attrs, updates, batch,
  local_ops_per_s: Math.round(updates / localS),
  remote_apply_ops_per_s: Math.round(updates / remoteS),
  bytes_per_update: Math.round((bytes / updates) * 100) / 100,
  state_bytes: Y.encodeStateAsUpdate(a).length,
  replicas_equal: same,
}));
