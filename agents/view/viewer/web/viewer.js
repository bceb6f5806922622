// Quiver's viewer page: the symbolic graph (d3 force layout on a canvas), the kinematic tree with
// its collision shapes (three.js), an inspector, and a timeline of the frames the server kept.
// Protocol: docs/viewer.md. Tests and benchmarks read window.quiver.
'use strict';

const quiver = window.quiver = {
  nodes: new Map(),      // key -> node object (server JSON + layout x, y)
  edges: new Map(),      // "from|type|to" -> edge object
  live: true, frame: null, fps: 0, frames: 0, changes: 0, loadedMs: null, readyMs: null,
  appearedAt: {},        // node name -> Date.now() when it first appeared on the page
  highlight: new Map(),  // key -> until (performance.now())
  hideGeometry: false, selected: null, filter: '',
  schema: null,          // the shared vocabulary the viewer was given (docs/schema.md), or null
};

const $ = (id) => document.getElementById(id);
const edgeKey = (e) => e.from + '|' + e.type + '|' + e.to;
const HIGHLIGHT_MS = 1500;

// ---- graph view: d3 v3 force layout drawn on a canvas ----
const canvas = $('graph');
const ctx = canvas.getContext('2d');
let view = { x: 0, y: 0, k: 1 };
let width = 0, height = 0, dirty = true;
const force = d3.layout.force().charge(-140).linkDistance(70).gravity(0.06).friction(0.85)
  .on('tick', () => { dirty = true; });
const zoom = d3.behavior.zoom().scaleExtent([0.05, 8]).on('zoom', () => {
  view = { x: d3.event.translate[0], y: d3.event.translate[1], k: d3.event.scale }; dirty = true;
});
d3.select(canvas).call(zoom);

function resize() {
  const r = canvas.getBoundingClientRect();
  width = r.width; height = r.height;
  canvas.width = width * devicePixelRatio; canvas.height = height * devicePixelRatio;
  force.size([width, height]);
  three.resize();
  dirty = true;
}

function visibleNode(n) { return !(quiver.hideGeometry && n.geometric); }

function layoutGraph(reheat) {
  const nodes = [], links = [];
  for (const n of quiver.nodes.values()) if (visibleNode(n)) nodes.push(n);
  for (const e of quiver.edges.values()) {
    const s = quiver.nodes.get(e.from), t = quiver.nodes.get(e.to);
    if (s && t && visibleNode(s) && visibleNode(t)) links.push({ source: s, target: t, edge: e });
  }
  if (!quiver.hideGeometry)
    for (const n of quiver.nodes.values())
      if (n.pose && quiver.nodes.has(n.pose.parent))
        links.push({ source: quiver.nodes.get(n.pose.parent), target: n, rt: true });
  quiver.links = links;
  force.nodes(nodes).links(links);
  dirty = true;
  // A big graph is drawn where it was placed first, and laid out from the next frame on.
  const start = () => { force.start(); force.alpha(reheat); };
  if (nodes.length > 3000) requestAnimationFrame(() => requestAnimationFrame(start)); else start();
}

// A new node starts next to a node it is linked to, so the layout moves little.
const neighbours = new Map();  // key -> Set of keys linked to it by a symbolic edge
function link(e, on) {
  for (const [a, b] of [[e.from, e.to], [e.to, e.from]]) {
    if (!neighbours.has(a)) neighbours.set(a, new Set());
    if (on) neighbours.get(a).add(b); else neighbours.get(a).delete(b);
  }
}
function placeNear(n) {
  if (n.x !== undefined) return;
  let anchor = n.pose ? quiver.nodes.get(n.pose.parent) : undefined;
  if (!anchor || anchor.x === undefined)
    for (const k of neighbours.get(n.id) || []) { const m = quiver.nodes.get(k); if (m && m.x !== undefined) { anchor = m; break; } }
  const i = quiver.nodes.size;
  if (anchor && anchor.x !== undefined) { n.x = anchor.x + 20 * Math.cos(i); n.y = anchor.y + 20 * Math.sin(i); }
  else { const r = 10 * Math.sqrt(i); n.x = width / 2 + r * Math.cos(i * 2.4); n.y = height / 2 + r * Math.sin(i * 2.4); }
  n.px = n.x; n.py = n.y;
}

function drawGraph() {
  const now = performance.now();
  ctx.setTransform(devicePixelRatio, 0, 0, devicePixelRatio, 0, 0);
  ctx.clearRect(0, 0, width, height);
  ctx.translate(view.x, view.y); ctx.scale(view.k, view.k);
  const labels = quiver.nodes.size <= 600 || view.k > 1.5;
  for (const l of quiver.links || []) {
    const s = l.source, t = l.target;
    if (s.x === undefined || t.x === undefined) continue;
    const lit = l.edge && quiver.highlight.get(edgeKey(l.edge)) > now;
    ctx.strokeStyle = lit ? '#ff6f00' : l.rt ? '#b0bec5' : (l.edge.colour || '#90a4ae');
    ctx.lineWidth = (lit ? 3 : 1.2) / Math.sqrt(view.k);
    ctx.setLineDash(l.rt ? [4, 3] : []);
    ctx.beginPath(); ctx.moveTo(s.x, s.y); ctx.lineTo(t.x, t.y); ctx.stroke();
    if (!l.rt) {  // arrow head and type
      const a = Math.atan2(t.y - s.y, t.x - s.x), hx = t.x - 9 * Math.cos(a), hy = t.y - 9 * Math.sin(a);
      ctx.beginPath(); ctx.moveTo(hx, hy);
      ctx.lineTo(hx - 7 * Math.cos(a - 0.4), hy - 7 * Math.sin(a - 0.4));
      ctx.lineTo(hx - 7 * Math.cos(a + 0.4), hy - 7 * Math.sin(a + 0.4));
      ctx.closePath(); ctx.fillStyle = ctx.strokeStyle; ctx.fill();
      if (labels) { ctx.fillStyle = '#546e7a'; ctx.font = '10px sans-serif'; ctx.fillText(l.edge.type, (s.x + t.x) / 2 + 3, (s.y + t.y) / 2 - 3); }
    }
  }
  ctx.setLineDash([]);
  for (const n of force.nodes()) {
    const lit = quiver.highlight.get(n.id) > now;
    const r = n.geometric ? 4 : 8;
    if (lit) { ctx.beginPath(); ctx.arc(n.x, n.y, r + 6, 0, 2 * Math.PI); ctx.fillStyle = 'rgba(255,111,0,.35)'; ctx.fill(); }
    ctx.beginPath(); ctx.arc(n.x, n.y, r, 0, 2 * Math.PI);
    ctx.fillStyle = n.colour; ctx.fill();
    ctx.lineWidth = n.violations.length ? 3 : n.lock ? 2.5 : 1;
    ctx.strokeStyle = n.violations.length ? '#c62828' : n.lock ? '#6a1b9a' : quiver.selected === n.id ? '#000' : '#fff';
    ctx.stroke();
    if (labels) {
      ctx.fillStyle = '#263238'; ctx.font = '11px sans-serif';
      ctx.fillText((n.lock ? '🔒 ' : '') + n.name, n.x + r + 2, n.y + 4);
    }
  }
}

// Clicks pick the nearest node (or an edge's midpoint) under the pointer.
canvas.addEventListener('click', (ev) => {
  const r = canvas.getBoundingClientRect();
  const x = (ev.clientX - r.left - view.x) / view.k, y = (ev.clientY - r.top - view.y) / view.k;
  let best = null, bestD = 14 / view.k;
  for (const n of force.nodes()) { const d = Math.hypot(n.x - x, n.y - y); if (d < bestD) { best = { node: n }; bestD = d; } }
  if (!best) for (const l of quiver.links || []) {
    if (!l.edge) continue;
    const d = Math.hypot((l.source.x + l.target.x) / 2 - x, (l.source.y + l.target.y) / 2 - y);
    if (d < bestD) { best = { edge: l.edge }; bestD = d; }
  }
  if (best && best.node) inspectNode(best.node.id); else if (best) inspectEdge(edgeKey(best.edge));
});

// ---- 3D view: one Object3D per frame, nested as the RT tree ----
const three = (() => {
  const pane = $('three-pane');
  let renderer = null;
  try { renderer = new THREE.WebGLRenderer({ antialias: true }); } catch (e) { pane.textContent = 'no WebGL: ' + e.message; }
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(50, 1, 0.01, 1000);
  camera.up.set(0, 0, 1); camera.position.set(4, -5, 4);
  scene.add(new THREE.AmbientLight(0xffffff, 0.55));
  const sun = new THREE.DirectionalLight(0xffffff, 0.7); sun.position.set(3, -2, 6); scene.add(sun);
  scene.add(new THREE.AxesHelper(0.5));
  const grid = new THREE.GridHelper(10, 20, 0x445566, 0x2a3440); grid.rotation.x = Math.PI / 2; scene.add(grid);
  let controls = null;
  if (renderer) { pane.appendChild(renderer.domElement); controls = new THREE.OrbitControls(camera, renderer.domElement); }
  const objects = new Map();  // key -> { obj, shapeKey }
  const pending = new Map();  // key -> pose, applied once per animation frame

  function objectFor(key) {
    let o = objects.get(key);
    if (!o) { o = { obj: new THREE.Group(), shapeKey: '' }; o.obj.name = key; objects.set(key, o); scene.add(o.obj); }
    return o;
  }
  function meshFor(shape, colour) {
    const m = new THREE.MeshLambertMaterial({ color: colour, transparent: true, opacity: 0.85 });
    let g;
    if (shape.kind === 'box') g = new THREE.BoxBufferGeometry(shape.size[0], shape.size[1], shape.size[2]);
    else if (shape.kind === 'sphere') g = new THREE.SphereBufferGeometry(shape.radius, 16, 12);
    else if (shape.kind === 'cylinder' || shape.kind === 'capsule') {
      const grp = new THREE.Group();
      const c = new THREE.Mesh(new THREE.CylinderBufferGeometry(shape.radius, shape.radius, shape.length, 16), m);
      c.rotation.x = Math.PI / 2;  // three's cylinders run along y; ours along z
      grp.add(c);
      if (shape.kind === 'capsule') for (const s of [-1, 1]) {
        const cap = new THREE.Mesh(new THREE.SphereBufferGeometry(shape.radius, 12, 8), m);
        cap.position.z = s * shape.length / 2; grp.add(cap);
      }
      return grp;
    } else g = new THREE.BoxBufferGeometry(0.1, 0.1, 0.1);  // a mesh file: a marker (see docs/viewer.md)
    return new THREE.Mesh(g, shape.kind === 'mesh' ? new THREE.MeshBasicMaterial({ color: colour, wireframe: true }) : m);
  }
  // A frame without a collision shape: a small dot, so the tree shows.
  function marker(colour) { return new THREE.Mesh(new THREE.SphereBufferGeometry(0.025, 8, 6), new THREE.MeshBasicMaterial({ color: colour })); }
  function setPose(o, p) {
    o.obj.position.set(p.t[0], p.t[1], p.t[2]);
    o.obj.quaternion.set(p.q[1], p.q[2], p.q[3], p.q[0]);
  }
  return {
    objects, pending,
    resize() {
      if (!renderer) return;
      const r = pane.getBoundingClientRect();
      renderer.setSize(r.width, r.height); camera.aspect = r.width / Math.max(1, r.height); camera.updateProjectionMatrix();
    },
    upsert(n) {  // a node with an RT parent, RT children or a shape
      const o = objectFor(n.id);
      const parent = n.pose && objects.has(n.pose.parent) ? objects.get(n.pose.parent).obj
                   : n.pose ? objectFor(n.pose.parent).obj : scene;
      if (o.obj.parent !== parent) parent.add(o.obj);
      if (n.pose) setPose(o, n.pose);
      const sk = JSON.stringify(n.shape) + n.colour;
      if (sk !== o.shapeKey) {
        o.shapeKey = sk;
        if (o.mesh) o.obj.remove(o.mesh);
        o.mesh = n.shape ? meshFor(n.shape, n.colour) : marker(n.colour);
        if (o.mesh) o.obj.add(o.mesh);
      }
    },
    remove(key) {
      const o = objects.get(key);
      if (!o) return;
      for (const c of [...o.obj.children]) if (c.type === 'Group' && objects.has(c.name)) scene.add(c);
      o.obj.parent.remove(o.obj); objects.delete(key);
    },
    clear() { for (const k of [...objects.keys()]) this.remove(k); },
    frame() {
      for (const [key, p] of pending) { const o = objects.get(key); if (o) setPose(o, p); }
      pending.clear();
      if (renderer) { controls.update(); renderer.render(scene, camera); }
    },
  };
})();

// ---- the model: snapshots and change messages ----
function putNode(n) {
  const old = quiver.nodes.get(n.id);
  if (old) { Object.assign(old, n); n = old; } else { quiver.nodes.set(n.id, n); placeNear(n); }
  if (!(n.name in quiver.appearedAt)) quiver.appearedAt[n.name] = Date.now();
  if (n.pose || n.shape) three.upsert(n);
  return n;
}
function dropNode(key) { quiver.nodes.delete(key); three.remove(key); }

function loadSnapshot(s) {
  quiver.nodes.clear(); quiver.edges.clear(); neighbours.clear(); three.clear();
  for (const e of s.edges) { quiver.edges.set(edgeKey(e), e); link(e, true); }
  // Parents first, so each 3D object finds its parent.
  const byKey = new Map(s.nodes.map((n) => [n.id, n]));
  const done = new Set();
  const visit = (n) => {
    if (done.has(n.id)) return; done.add(n.id);
    if (n.pose && byKey.has(n.pose.parent)) visit(byKey.get(n.pose.parent));
    putNode(n);
  };
  s.nodes.forEach(visit);
  quiver.violations = s.violations;
  quiver.highlight.clear();
  const until = performance.now() + 1e9;
  for (const k of s.changed || []) quiver.highlight.set(k, until);
  for (const e of s.changed_edges || []) quiver.highlight.set(edgeKey(e), until);
  $('title').textContent = s.title; $('mode').textContent = s.mode;
  showAgents(s.agents || []); legend(s.types || {});
  layoutGraph(quiver.nodes.size > 3000 ? 0.02 : 0.1);
  refreshInspector();
}

function applyChange(m) {
  const until = performance.now() + HIGHLIGHT_MS;
  let structural = false;
  for (const e of m.edges) { const k = edgeKey(e); if (!quiver.edges.has(k)) structural = true; quiver.edges.set(k, e); link(e, true); quiver.highlight.set(k, until); }
  for (const e of m.deleted_edges) { quiver.edges.delete(edgeKey(e)); link(e, false); structural = true; }
  for (const n of m.nodes) { if (!quiver.nodes.has(n.id)) structural = true; putNode(n); quiver.highlight.set(n.id, until); }
  for (const k of m.deleted_nodes) { dropNode(k); structural = true; }
  for (const p of m.poses) {
    const n = quiver.nodes.get(p.id);
    if (n) n.pose = p;
    three.pending.set(p.id, p);
  }
  quiver.violations = m.violations;
  quiver.changes++;
  setFrameEnd(m.frame_end);
  if (structural) layoutGraph(0.03); else dirty = true;
  const shown = (k) => k === quiver.selected || k === quiver.selectedEdge;
  if (m.nodes.some((n) => shown(n.id)) || m.edges.some((e) => shown(edgeKey(e))) ||
      m.deleted_nodes.some(shown) || m.deleted_edges.some((e) => shown(edgeKey(e))))
    refreshInspector();
}

let events = null;
async function goLive() {
  quiver.live = true; $('live').classList.add('on');
  if (events) events.close();
  const t0 = performance.now();
  const first = window.firstSnapshot;
  window.firstSnapshot = null;
  const s = first ? await first : await (await fetch('api/snapshot')).json();
  loadSnapshot(s);
  setFrameEnd(s.frame_end);
  quiver.frame = null;
  if (quiver.loadedMs === null) quiver.loadedMs = performance.now() - t0;
  events = new EventSource('api/events?from=' + s.msg);
  events.addEventListener('change', (ev) => { if (quiver.live) applyChange(JSON.parse(ev.data)); else setFrameEnd(JSON.parse(ev.data).frame_end); });
  events.addEventListener('agents', (ev) => showAgents(JSON.parse(ev.data)));
  events.addEventListener('resync', () => { if (quiver.live) goLive(); });
  events.onerror = () => { $('status').textContent = 'disconnected: retrying'; };
  events.onopen = () => { $('status').textContent = ''; };
}

// ---- timeline ----
let frameEnd = 0;
function setFrameEnd(end) {
  frameEnd = end;
  const scrub = $('scrub');
  scrub.max = Math.max(0, end - 1);
  if (quiver.live) { scrub.value = scrub.max; $('frame-label').textContent = end + ' frames (live)'; }
}
async function showFrame(i) {
  quiver.live = false; $('live').classList.remove('on');
  const r = await fetch('api/snapshot?at=' + i);
  const s = await r.json();
  if (!r.ok) { $('frame-label').textContent = s.error; return; }
  quiver.frame = s.frame;
  loadSnapshot(s);
  $('scrub').value = i;
  const f = s.frame;
  $('frame-label').textContent = `frame ${i} of ${frameEnd} · ${(f.t_ms / 1000).toFixed(3)} s · ${f.origin || '?'}`;
  listFrames(Math.max(0, i - 12), i);
}
function describe(f) {
  const s = f.summary;
  if (!s) return f.kind === 'state' ? 'state transfer' : 'no visible change';
  const parts = [];
  if (s.created.length) parts.push('created ' + s.created.join(', '));
  if (s.deleted.length) parts.push('deleted ' + s.deleted.join(', '));
  if (s.edges_created.length) parts.push('linked ' + s.edges_created.join(', '));
  if (s.edges_deleted.length) parts.push('unlinked ' + s.edges_deleted.join(', '));
  if (s.updated.length) parts.push('set ' + s.updated.join('; '));
  if (s.poses) parts.push(s.poses + ' pose(s)');
  return parts.join(' · ') || 'no visible change';
}
async function listFrames(from, selected) {
  const h = await (await fetch(`api/history?from=${from}&limit=25`)).json();
  const ol = $('frames'); ol.innerHTML = ''; ol.start = from;
  for (const f of h.frames) {
    const li = document.createElement('li');
    li.value = f.i;
    li.dataset.frame = f.i;
    li.textContent = `${(f.t_ms / 1000).toFixed(3)} s  ${f.origin}: ${describe(f)}`;
    if (f.i === selected) li.className = 'selected';
    li.onclick = () => showFrame(f.i);
    ol.appendChild(li);
  }
}
$('scrub').addEventListener('input', (ev) => showFrame(+ev.target.value));
$('live').addEventListener('click', goLive);

// ---- inspector, agents, legend ----
function esc(s) { return String(s).replace(/[&<>"]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c])); }
// With a schema: an attribute's unit beside its value, and what its declaration says (type,
// range, writers) as the row's tooltip.
function declared(name) {
  const a = quiver.schema && quiver.schema.attributes && quiver.schema.attributes[name];
  if (!a) return null;
  const range = a.min !== undefined || a.max !== undefined ? ` in [${a.min ?? ''}, ${a.max ?? ''}]` : '';
  return { unit: a.unit || '', title: `declared ${a.type}${range}${a.writers ? ', written by ' + a.writers.join(', ') : ''}` };
}
function attrRows(attrs) {
  let h = '<table><tr><th>attribute</th><th>type</th><th>value</th><th>writer</th></tr>';
  for (const a of attrs) {
    const d = declared(a.name.startsWith('rt:') ? a.name.slice(3) : a.name);
    a.values.forEach((v, i) => {
      h += `<tr class="${a.values.length > 1 ? 'conflict' : ''}"${d ? ` title="${esc(d.title)}"` : ''}><td>${i ? '' : esc(a.name)}</td><td>${i ? '' : a.type}</td>` +
           `<td>${esc(JSON.stringify(v.v))}${d && d.unit ? ` <span class="unit">${esc(d.unit)}</span>` : ''}</td><td>${esc(v.writer)}</td></tr>`;
    });
  }
  return h + '</table>';
}
// A node type as the schema declares it: with its bases ("mug: cup, object"); undeclared types
// are marked when there is a schema.
function typeText(type) {
  const s = quiver.schema;
  if (!s || !s.node_types) return esc(type);
  const t = s.node_types[type];
  if (!t) return `${esc(type)}, <span class="violation">not in the schema</span>`;
  const is = t.is === undefined ? [] : [].concat(t.is);
  return esc(type) + (is.length ? ': ' + is.map(esc).join(', ') : '');
}
function inspectNode(key) { quiver.selected = key; quiver.selectedEdge = null; refreshInspector(); dirty = true; }
function inspectEdge(key) { quiver.selected = null; quiver.selectedEdge = key; refreshInspector(); }
function refreshInspector() {
  const el = $('inspector');
  if (quiver.selected && quiver.nodes.has(quiver.selected)) {
    const n = quiver.nodes.get(quiver.selected);
    let h = `<h3>${esc(n.name)} <small>(${typeText(n.type)})</small></h3><div>id ${n.id}</div>`;
    if (n.pose) h += `<div>RT parent ${esc((quiver.nodes.get(n.pose.parent) || { name: n.pose.parent }).name)}, t = [${n.pose.t.map((x) => x.toFixed(3))}]</div>`;
    if (n.lock) h += `<div class="lock">locked by ${esc(n.lock.holder)} (epoch ${n.lock.epoch}, priority ${n.lock.priority})</div>`;
    for (const v of n.violations) h += `<div class="violation">violates ${esc(v)}</div>`;
    h += attrRows(n.attrs);
    for (const im of n.images)
      h += `<div>${esc(im.prefix)}:<br><img alt="${esc(im.prefix)}" src="api/image?node=${encodeURIComponent(n.id)}` +
           `&prefix=${encodeURIComponent(im.prefix)}&v=${encodeURIComponent(im.version)}"></div>`;
    el.innerHTML = h;
  } else if (quiver.selectedEdge && quiver.edges.has(quiver.selectedEdge)) {
    const e = quiver.edges.get(quiver.selectedEdge);
    const name = (k) => esc((quiver.nodes.get(k) || { name: k }).name);
    el.innerHTML = `<h3>${name(e.from)} -[${esc(e.type)}]-> ${name(e.to)}</h3>` + attrRows(e.attrs);
  }
}
// The agents heard, and in a team the robots reachable now (those with a live agent listed),
// each robot's agents after its name; this replica's robot first.
function showAgents(list) {
  const chip = (a) => `<span class="agent ${a.alive ? '' : 'gone'} ${a.observer ? 'observer' : ''} ${a.gateway ? 'gateway' : ''}"` +
    ` title="${esc(a.id)}${a.via ? ' via ' + esc(a.via) : ''}">${esc(a.name || a.id)}</span>`;
  const here = (list.find((a) => a.self) || {}).robot || '';
  const others = list.filter((a) => !a.self);
  if (!here && !others.some((a) => a.robot)) {
    $('agents').innerHTML = others.map(chip).join('');
  } else {
    const robots = [...new Set(others.filter((a) => a.alive && a.robot).map((a) => a.robot))]
      .filter((r) => r !== here).sort();
    const group = (r, label) => `<span class="robot" data-robot="${esc(r)}">${label}:</span>` +
      others.filter((a) => (a.robot || here) === r).map(chip).join('');
    $('agents').innerHTML = `<span class="robots">robots reachable: ${[here, ...robots].map(esc).join(', ')}</span> ` +
      [group(here, `robot ${esc(here)} (here)`), ...robots.map((r) => group(r, `robot ${esc(r)}`))].join(' ');
  }
  quiver.agents = list;
}
function legend(types) {
  $('legend').innerHTML = Object.keys(types).sort().map((t) => `<div><span style="background:${types[t]}"></span>${esc(t)}</div>`).join('');
}
$('hide-geometry').addEventListener('change', (ev) => { quiver.hideGeometry = ev.target.checked; layoutGraph(0.05); });
$('filter').addEventListener('change', (ev) => {
  const q = ev.target.value.trim();
  for (const n of quiver.nodes.values()) if (n.name === q || n.name.includes(q)) { inspectNode(n.id); break; }
});

// ---- test and benchmark hooks ----
quiver.visibleNodeNames = () => force.nodes().map((n) => n.name).sort();
quiver.nodeNames = () => [...quiver.nodes.values()].map((n) => n.name).sort();
quiver.objects3d = () => three.objects.size;
quiver.worldPosition = (name) => {
  for (const n of quiver.nodes.values()) if (n.name === name) {
    const o = three.objects.get(n.id); if (!o) return null;
    const v = new THREE.Vector3(); o.obj.getWorldPosition(v); return [v.x, v.y, v.z];
  }
  return null;
};
quiver.draw = drawGraph;
quiver.showFrame = showFrame; quiver.goLive = goLive; quiver.inspectNode = inspectNode;
quiver.inspectByName = (name) => { for (const n of quiver.nodes.values()) if (n.name === name) { inspectNode(n.id); return true; } return false; };

// ---- the animation loop: apply poses, draw, count frames ----
let fpsCount = 0, fpsSince = performance.now();
function animate(now) {
  three.frame();
  if (dirty || quiver.highlight.size) {
    drawGraph(); dirty = false;
    if (quiver.readyMs === null) quiver.readyMs = performance.now();  // since navigation began
  }
  for (const [k, until] of quiver.highlight) if (until < now) quiver.highlight.delete(k);
  quiver.frames++; fpsCount++;
  if (now - fpsSince >= 1000) { quiver.fps = fpsCount * 1000 / (now - fpsSince); fpsCount = 0; fpsSince = now; }
  requestAnimationFrame(animate);
}
window.addEventListener('resize', resize);
resize();
goLive().then(() => requestAnimationFrame(animate));
fetch('api/info').then((r) => r.json()).then((i) => { quiver.schema = i.schema || null; refreshInspector(); });
