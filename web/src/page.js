// report.html's script (docs/report.md): draws what cmcsurf put in #cmc-data. The 3D view of
// the surface (three.js), the controls, the convergence and curvature charts. Every number
// comes from the data; nothing is computed here but colours and chart coordinates.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const statusEl = document.getElementById('status');
const errors = [];
function fail(message) {
  errors.push(String(message));
  statusEl.textContent = 'error: ' + errors.join('; ');
  statusEl.className = 'error';
  statusEl.dataset.status = 'error';
}
window.addEventListener('error', (e) => fail(e.message || e));
window.addEventListener('unhandledrejection', (e) => fail(e.reason));
const consoleError = console.error.bind(console);
console.error = (...args) => {
  fail(args.join(' '));
  consoleError(...args);
};

const data = JSON.parse(document.getElementById('cmc-data').textContent);
const SVG = 'http://www.w3.org/2000/svg';
// The first view from the address: report.html#nodal&tiles=2, or #member=G_0.30&tiles=3.
const initial = (() => {
  const p = new URLSearchParams(window.location.hash.slice(1));
  const tiles = Number(p.get('tiles'));
  return { nodal: p.has('nodal'), member: p.get('member'), tiles: [1, 2, 3].includes(tiles) ? tiles : 1 };
})();

function decode(b64) {
  const s = atob(b64);
  const a = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) a[i] = s.charCodeAt(i);
  return a.buffer;
}

// The diverging colour at t in [0, 1] from cmcsurf's table (render/colormap.h).
function colorAt(t) {
  const stops = data.scale.stops;
  if (!(t > 0)) return stops[0].slice(1);
  if (t >= 1) return stops[stops.length - 1].slice(1);
  const x = t * (stops.length - 1);
  const i = Math.min(Math.floor(x), stops.length - 2);
  const f = x - i;
  return [1, 2, 3].map((c) => stops[i][c] + f * (stops[i + 1][c] - stops[i][c]));
}
const scaleT = (h) => 0.5 + (0.5 * (h - data.scale.centre)) / data.scale.half_range;

function geometry(mesh) {
  const g = new THREE.BufferGeometry();
  const normals8 = new Int8Array(decode(mesh.normals));
  const normals = new Float32Array(normals8.length);
  for (let i = 0; i < normals.length; i++) normals[i] = normals8[i] / 127;
  const h = new Float32Array(decode(mesh.curvature));
  const colors = new Float32Array(3 * h.length);
  const c = new THREE.Color();
  for (let i = 0; i < h.length; i++) {
    const [r, gg, b] = colorAt(scaleT(h[i]));
    c.setRGB(r, gg, b, THREE.SRGBColorSpace);
    colors[3 * i] = c.r;
    colors[3 * i + 1] = c.g;
    colors[3 * i + 2] = c.b;
  }
  const q = new Uint16Array(decode(mesh.positions));
  const positions = new Float32Array(q.length);
  for (let i = 0; i < q.length; i++) positions[i] = mesh.origin + q[i] / 65535;
  g.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  g.setAttribute('normal', new THREE.BufferAttribute(normals, 3));
  g.setAttribute('color', new THREE.BufferAttribute(colors, 3));
  const indices = mesh.index_bytes === 2 ? new Uint16Array(decode(mesh.indices)) : new Uint32Array(decode(mesh.indices));
  g.setIndex(new THREE.BufferAttribute(indices, 1));
  return g;
}

class Viewer {
  constructor(canvas) {
    this.canvas = canvas;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setSize(canvas.clientWidth, canvas.clientHeight, false);
    this.renderer.setClearColor(0xffffff, 1);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(30, canvas.clientWidth / canvas.clientHeight, 0.01, 200);
    this.camera.up.set(0, 0, 1);
    this.scene.add(new THREE.AmbientLight(0xffffff, 1.1));
    const light = new THREE.DirectionalLight(0xffffff, 2.0);
    light.position.set(-1, 1.5, 2);
    this.camera.add(light);
    this.scene.add(this.camera);
    this.material = new THREE.MeshPhongMaterial({
      vertexColors: true, side: THREE.DoubleSide, shininess: 40, specular: 0x222222,
    });
    this.outline = new THREE.LineBasicMaterial({ color: 0x8c8c94 });
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener('change', () => this.render());
    this.group = null;
    this.tiles = 0;
  }
  show(geom, origin, tiles) {
    if (this.group) this.scene.remove(this.group);
    this.group = new THREE.Group();
    for (let z = 0; z < tiles; z++)
      for (let y = 0; y < tiles; y++)
        for (let x = 0; x < tiles; x++) {
          const m = new THREE.Mesh(geom, this.material);
          m.position.set(x, y, z);
          this.group.add(m);
        }
    const box = new THREE.LineSegments(
      new THREE.EdgesGeometry(new THREE.BoxGeometry(tiles, tiles, tiles)), this.outline);
    box.position.set(origin + tiles / 2, origin + tiles / 2, origin + tiles / 2);
    this.group.add(box);
    const c = origin + tiles / 2;
    this.group.position.set(-c, -c, -c);
    this.scene.add(this.group);
    if (tiles !== this.tiles) {  // keep the user's rotation, refit the distance
      const dir = this.tiles ? this.camera.position.clone().normalize()
        : new THREE.Vector3(Math.cos(0.52) * Math.cos(0.42), Math.sin(0.52) * Math.cos(0.42), Math.sin(0.42));
      this.camera.position.copy(dir.multiplyScalar(3.4 * tiles));
      this.controls.target.set(0, 0, 0);
      this.controls.update();
      this.tiles = tiles;
    }
    this.render();
  }
  render() {
    this.renderer.render(this.scene, this.camera);
  }
}

function el(tag, attrs = {}, parent = null, text = null) {
  const e = tag.startsWith('svg:') ? document.createElementNS(SVG, tag.slice(4)) : document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== null) e.textContent = text;
  if (parent) parent.appendChild(e);
  return e;
}

const fmt = (v) => (Math.abs(v) >= 1e4 || (Math.abs(v) < 1e-3 && v !== 0) ? v.toExponential(2) : Number(v.toPrecision(4)).toString());

// The colour bar of the current scale, with five ticks.
function colorBar(parent) {
  const box = el('div', { style: 'margin-top: 10px' }, parent);
  el('div', { style: 'margin-bottom: 10px' }, box, 'local mean curvature H');
  const stops = data.scale.stops.map((s) => `rgb(${s.slice(1).map((x) => Math.round(255 * x)).join(',')}) ${100 - 100 * s[0]}%`);
  el('div', { class: 'bar', style: `background: linear-gradient(to bottom, ${stops.reverse().join(', ')})` }, box);
  const ticks = el('div', { class: 'ticks' }, box);
  for (let k = 0; k <= 4; k++) {
    const v = data.scale.centre + (1 - k / 2) * data.scale.half_range;
    el('span', { style: `top: ${k * 25}%` }, ticks, (v >= 0 ? '+' : '') + fmt(v));
  }
}

// A line chart of ys against xs (nulls skipped), optionally on a log scale.
function lineChart(parent, title, xs, series, opts = {}) {
  const W = 360, H = 220, L = 58, R = 10, T = 22, B = 34;
  const svg = el('svg:svg', { width: W, height: H, class: 'chart', 'data-title': title }, parent);
  el('svg:text', { x: L, y: 14 }, svg, title);
  const tr = opts.log ? (v) => Math.log10(v) : (v) => v;
  const pts = series.map((s) => xs.map((x, i) => [x, s.ys[i]]).filter(([x, y]) => y !== null && isFinite(y) && (!opts.log || y > 0)));
  const all = pts.flat();
  if (!all.length) return svg;
  let [x0, x1] = [Math.min(...all.map((p) => p[0])), Math.max(...all.map((p) => p[0]))];
  let [y0, y1] = [Math.min(...all.map((p) => tr(p[1]))), Math.max(...all.map((p) => tr(p[1])))];
  if (x1 === x0) x1 = x0 + 1;
  if (y1 === y0) { y0 -= 0.5; y1 += 0.5; }
  const sx = (x) => L + ((x - x0) / (x1 - x0)) * (W - L - R);
  const sy = (y) => T + (1 - (tr(y) - y0) / (y1 - y0)) * (H - T - B);
  el('svg:rect', { x: L, y: T, width: W - L - R, height: H - T - B, fill: 'none', stroke: '#bbb' }, svg);
  for (const [k, v] of [[0, y0], [1, y1]]) {
    const label = opts.log ? Math.pow(10, v).toExponential(0) : fmt(v);
    el('svg:text', { x: L - 4, y: k ? T + 4 : H - B, 'text-anchor': 'end' }, svg, label);
  }
  el('svg:text', { x: L, y: H - B + 14 }, svg, fmt(x0));
  el('svg:text', { x: W - R, y: H - B + 14, 'text-anchor': 'end' }, svg, fmt(x1));
  el('svg:text', { x: (L + W) / 2, y: H - 4, 'text-anchor': 'middle' }, svg, opts.xlabel || 'step');
  pts.forEach((p, k) => {
    const d = p.map(([x, y], i) => (i ? 'L' : 'M') + sx(x).toFixed(1) + ' ' + sy(y).toFixed(1)).join('');
    el('svg:path', { d, fill: 'none', stroke: series[k].color, 'stroke-width': 1.5 }, svg);
  });
  return svg;
}

function histogramChart(parent, hist) {
  const W = 520, H = 240, L = 50, R = 10, T = 22, B = 34;
  const svg = el('svg:svg', { width: W, height: H, class: 'chart', 'data-title': 'histogram' }, parent);
  el('svg:text', { x: L, y: 14 }, svg, 'fraction of the surface area per bin of local H');
  const lo = hist.H_lo, hi = hist.H_hi, n = lo.length;
  const series = [['relaxed', '#2b5cd6'], ['nodal', '#e07b1a']].filter(([k]) => hist[k] && hist[k].some((v) => v));
  const ymax = Math.max(...series.flatMap(([k]) => hist[k])) || 1;
  const x0 = lo[0], x1 = hi[n - 1];
  const sx = (x) => L + ((x - x0) / (x1 - x0)) * (W - L - R);
  const sy = (y) => T + (1 - y / ymax) * (H - T - B);
  el('svg:rect', { x: L, y: T, width: W - L - R, height: H - T - B, fill: 'none', stroke: '#bbb' }, svg);
  series.forEach(([k, color], s) => {
    for (let i = 0; i < n; i++) {
      const w = (sx(hi[i]) - sx(lo[i])) / series.length;
      el('svg:rect', { x: sx(lo[i]) + s * w, y: sy(hist[k][i]), width: Math.max(w - 0.5, 0.5), height: sy(0) - sy(hist[k][i]), fill: color }, svg);
    }
    el('svg:text', { x: W - R - 4, y: T + 14 + 14 * s, 'text-anchor': 'end', fill: color }, svg, k);
  });
  el('svg:line', { x1: sx(data.mean_curvature), x2: sx(data.mean_curvature), y1: T, y2: H - B, stroke: '#222', 'stroke-dasharray': '3 3' }, svg);
  el('svg:text', { x: L, y: H - B + 14 }, svg, fmt(x0));
  el('svg:text', { x: W - R, y: H - B + 14, 'text-anchor': 'end' }, svg, fmt(x1));
  el('svg:text', { x: (L + W) / 2, y: H - 4, 'text-anchor': 'middle' }, svg, 'local H (dashed: the surface mean)');
  el('svg:text', { x: L - 4, y: T + 4, 'text-anchor': 'end' }, svg, fmt(ymax));
}

function runPage(viewer, controls) {
  const geoms = { relaxed: geometry(data.relaxed), nodal: data.nodal ? geometry(data.nodal) : null };
  const state = { which: initial.nodal && geoms.nodal ? 'nodal' : 'relaxed', tiles: initial.tiles };
  const update = () => {
    viewer.show(geoms[state.which], data.relaxed.origin, state.tiles);
    statusEl.dataset.shown = `${state.which},${state.tiles}`;
  };
  const twin = el('label', {}, controls);
  const box = el('input', { type: 'checkbox', id: 'nodal-toggle' }, twin);
  box.checked = state.which === 'nodal';
  twin.appendChild(document.createTextNode(' nodal twin (same volume fraction)'));
  if (!geoms.nodal) { box.disabled = true; twin.title = 'this surface has no nodal formula'; }
  box.addEventListener('change', () => { state.which = box.checked && geoms.nodal ? 'nodal' : 'relaxed'; update(); });
  const tiles = el('div', {}, controls, 'tiles: ');
  for (const t of [1, 2, 3]) {
    const l = el('label', { style: 'display: inline; margin-right: 8px' }, tiles);
    const r = el('input', { type: 'radio', name: 'tiles', value: t, id: `tiles-${t}` }, l);
    if (t === state.tiles) r.checked = true;
    l.appendChild(document.createTextNode(` ${t}³`));
    r.addEventListener('change', () => { state.tiles = t; update(); });
  }
  colorBar(controls);
  update();
  const h = data.history;
  const hist = document.getElementById('history');
  lineChart(hist, 'area', h.step, [{ ys: h.area, color: '#2b5cd6' }]);
  lineChart(hist, '|dA| per step', h.step, [{ ys: h.d_area.map((v) => (v === null ? null : Math.abs(v))), color: '#c0392b' }], { log: true });
  lineChart(hist, 'V-cycles per step', h.step, [{ ys: h.vcycles, color: '#333' }]);
  histogramChart(document.getElementById('histogram'), data.histogram);
}

function sweepPage(viewer, controls) {
  const geoms = new Map();
  const label = el('div', { id: 'member-label' }, controls);
  const state = { member: Math.max(0, data.members.findIndex((m) => m.name === initial.member)),
    tiles: initial.tiles };
  const rows = [...document.querySelectorAll('tr.member')];
  const update = () => {
    const m = data.members[state.member];
    if (!geoms.has(m.name)) geoms.set(m.name, geometry(m.mesh));
    viewer.show(geoms.get(m.name), m.mesh.origin, state.tiles);
    label.textContent = `${m.name}: H = ${(m.mean_curvature >= 0 ? '+' : '') + fmt(m.mean_curvature)}`;
    rows.forEach((r) => r.classList.toggle('selected', r.dataset.member === m.name));
    statusEl.dataset.shown = `${m.name},${state.tiles}`;
  };
  rows.forEach((r) => r.addEventListener('click', () => {
    state.member = data.members.findIndex((m) => m.name === r.dataset.member);
    update();
  }));
  const tiles = el('div', {}, controls, 'tiles: ');
  for (const t of [1, 2, 3]) {
    const l = el('label', { style: 'display: inline; margin-right: 8px' }, tiles);
    const r = el('input', { type: 'radio', name: 'tiles', value: t }, l);
    if (t === state.tiles) r.checked = true;
    l.appendChild(document.createTextNode(` ${t}³`));
    r.addEventListener('change', () => { state.tiles = t; update(); });
  }
  colorBar(controls);
  update();
}

// A printed part (cmcsurf scaffold's FILE.html): the part scaled into the unit cube, coloured
// by height, with no tiles.
function partPage(viewer, controls) {
  viewer.show(geometry(data.part), data.part.origin, 1);
  el('div', { id: 'part-label' }, controls,
    `${data.part.triangles} triangles drawn; colour: height, bottom (blue) to top (red)`);
  statusEl.dataset.shown = 'part';
}

function main() {
  const canvas = document.getElementById('view');
  const controls = document.getElementById('controls');
  let viewer;
  try {
    viewer = new Viewer(canvas);
  } catch (e) {
    statusEl.textContent = 'no 3D view: WebGL is not available in this browser (' + e.message + ')';
    statusEl.dataset.status = 'no-webgl';
    statusEl.className = 'error';
    return;
  }
  if (data.kind === 'sweep') sweepPage(viewer, controls);
  else if (data.kind === 'part') partPage(viewer, controls);
  else runPage(viewer, controls);
  if (!errors.length) {
    statusEl.textContent = '3D view: drag to rotate, scroll to zoom, right-drag to pan';
    statusEl.dataset.status = 'ok';
  }
  // Where the view is, for a test that looks at a screenshot of the page.
  const r = canvas.getBoundingClientRect();
  statusEl.dataset.canvas = [r.left, r.top, r.right, r.bottom].map(Math.round).join(',');
}

main();
