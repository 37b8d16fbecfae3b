// The live page's module: follows /events (one state per iteration), fetches
// the filtered field (/field.f32, float32 cd per cube-map texel) when it
// changes, and draws the unfolded cube, the sphere (three.js), the polar
// curves and the numbers. Every number element carries its raw value in
// data-value, so scripts and tests can read what the page shows.
//
// Cube-map layout (sim/detectors/cube_map.h): faces +X, −X, +Y, −Y, +Z, −Z; texel
// (face, x, y) at index (face·N + y)·N + x; face coordinates a, b at texel
// centres give the directions +X (1, −b, a), −X (−1, −b, −a), +Y (a, 1, −b),
// −Y (a, −1, b), +Z (−a, −b, 1), −Z (a, −b, −1).

const $ = (id) => document.getElementById(id);

const page = {
  state: null,        // the latest state.json
  field: null,        // Float32Array of the latest field
  fieldVersion: -1,
  updates: [],        // arrival times of states with a new iteration [ms]
  drawnCurves: null,  // the curves the diagrams show (tests read this)
  cubeScale: 'lin',
  sphereMode: 'sphere',
};
window.gonioPage = page;

// ---------- formatting ----------
function fmt(v, digits = 3) {
  if (v === null || v === undefined || !Number.isFinite(v)) return '—';
  const a = Math.abs(v);
  if (a !== 0 && (a >= 1e6 || a < 1e-3)) return v.toExponential(digits - 1);
  return v.toLocaleString('en-US', { maximumSignificantDigits: Math.max(digits, Math.ceil(Math.log10(a + 1))) });
}
function fmtCount(v) {
  if (!Number.isFinite(v)) return '—';
  if (v >= 1e9) return (v / 1e9).toFixed(2) + ' G';
  if (v >= 1e6) return (v / 1e6).toFixed(2) + ' M';
  if (v >= 1e3) return (v / 1e3).toFixed(1) + ' k';
  return String(v);
}
function fmtTime(s) {
  if (s === null || s === undefined || !Number.isFinite(s)) return '—';
  if (s < 1) return (s * 1000).toFixed(0) + ' ms';
  if (s < 60) return s.toFixed(1) + ' s';
  return Math.floor(s / 60) + ' min ' + String(Math.round(s % 60)).padStart(2, '0') + ' s';
}
function setNumber(id, value, text) {
  const el = $(id);
  el.dataset.value = value === null || value === undefined ? '' : String(value);
  el.textContent = text;
}

// ---------- false colour ----------
// Stops of the page's own colour ramp (dark → blue → teal → green → yellow → white).
const RAMP = [
  [0.00, [12, 14, 26]], [0.15, [38, 40, 110]], [0.32, [30, 100, 170]], [0.50, [32, 160, 150]],
  [0.68, [120, 200, 80]], [0.84, [240, 210, 60]], [1.00, [255, 250, 225]],
];
function ramp(t) {
  t = Math.min(1, Math.max(0, t));
  for (let i = 1; i < RAMP.length; ++i) {
    if (t <= RAMP[i][0]) {
      const [t0, c0] = RAMP[i - 1], [t1, c1] = RAMP[i];
      const u = (t - t0) / (t1 - t0);
      return [c0[0] + u * (c1[0] - c0[0]), c0[1] + u * (c1[1] - c0[1]), c0[2] + u * (c1[2] - c0[2])];
    }
  }
  return RAMP[RAMP.length - 1][1];
}
// The top of the colour scale: the white point (99 % of the flux under it,
// as preview.png) on the linear scale, the peak on the log scale.
function scaleTop(field) {
  return page.cubeScale === 'log' || !(field.white_cd > 0) ? field.max_cd : field.white_cd;
}
// Maps cd to [0, 1] on the current scale: linear 0…top (brighter clips to
// white), or log over 4 decades below the top.
function scaler(maxCd) {
  if (!(maxCd > 0)) return () => 0;
  if (page.cubeScale === 'log') {
    const lo = maxCd * 1e-4;
    return (v) => (v <= lo ? 0 : Math.log10(v / lo) / 4);
  }
  return (v) => v / maxCd;
}

// ---------- the unfolded cube ----------
const SLOTS = [[2, 1], [0, 1], [1, 0], [1, 2], [3, 1], [1, 1]];  // +X, −X, +Y, −Y, +Z, −Z
function drawCube() {
  const s = page.state, f = page.field;
  if (!s || !s.field || !f) return;
  const n = s.field.face_size, maxCd = scaleTop(s.field);
  if (f.length !== 6 * n * n) return;
  const canvas = $('cube');
  if (canvas.width !== 4 * n) { canvas.width = 4 * n; canvas.height = 3 * n; }
  const ctx = canvas.getContext('2d');
  const img = ctx.createImageData(4 * n, 3 * n);
  const scale = scaler(maxCd);
  for (let face = 0; face < 6; ++face) {
    const [col, row] = SLOTS[face];
    for (let y = 0; y < n; ++y) {
      for (let x = 0; x < n; ++x) {
        const c = ramp(scale(f[(face * n + y) * n + x]));
        const o = 4 * ((row * n + y) * 4 * n + col * n + x);
        img.data[o] = c[0]; img.data[o + 1] = c[1]; img.data[o + 2] = c[2]; img.data[o + 3] = 255;
      }
    }
  }
  ctx.putImageData(img, 0, 0);
  ctx.font = `${Math.max(10, n / 9)}px DejaVu Sans, sans-serif`;
  ctx.fillStyle = 'rgba(255,255,255,0.75)';
  const labels = ['+X', '−X', '+Y', '−Y (nadir)', '+Z', '−Z'];
  for (let face = 0; face < 6; ++face) {
    const [col, row] = SLOTS[face];
    ctx.fillText(labels[face], col * n + 5, row * n + n / 9 + 3);
  }
  drawScale(maxCd);
}
function drawScale(maxCd) {
  const bar = $('scale-bar'), ctx = bar.getContext('2d');
  for (let y = 0; y < bar.height; ++y) {
    const c = ramp(1 - y / (bar.height - 1));
    ctx.fillStyle = `rgb(${c[0] | 0},${c[1] | 0},${c[2] | 0})`;
    ctx.fillRect(0, y, bar.width, 1);
  }
  const ticks = $('scale-ticks');
  ticks.innerHTML = '';
  const values = page.cubeScale === 'log'
    ? [0, 1, 2, 3, 4].map((k) => maxCd * Math.pow(10, -k))
    : [1, 0.75, 0.5, 0.25, 0].map((k) => maxCd * k);
  for (const v of values) {
    const d = document.createElement('div');
    d.textContent = (v === values[0] && page.cubeScale === 'lin' && page.state.field.white_cd < page.state.field.max_cd
      ? '≥ ' : '') + fmt(v, 3) + ' cd';
    ticks.appendChild(d);
  }
}

// ---------- polar curves ----------
function polar(canvasId, cur, prev, planeA, planeB, colour, title) {
  const canvas = $(canvasId), ctx = canvas.getContext('2d');
  const W = canvas.width, H = canvas.height;
  ctx.clearRect(0, 0, W, H);
  const cx = W / 2, cy = H * 0.47, R = Math.min(W / 2, H * 0.47) - 26;
  const series = [];
  if (cur && cur.gamma_deg) series.push({ c: cur, dash: false });
  if (prev && prev.gamma_deg) series.push({ c: prev, dash: true });
  let maxCd = 0;
  for (const s of series) for (const k of [planeA, planeB]) for (const v of s.c[k] || []) maxCd = Math.max(maxCd, v);
  const niceMax = niceCeil(maxCd);
  // Grid: circles at quarters of the scale, spokes every 30° of γ.
  ctx.strokeStyle = '#2b3240'; ctx.lineWidth = 1; ctx.fillStyle = '#7d879a';
  ctx.font = '12px DejaVu Sans, sans-serif';
  for (let k = 1; k <= 4; ++k) {
    ctx.beginPath(); ctx.arc(cx, cy, (R * k) / 4, 0, 2 * Math.PI); ctx.stroke();
    if (niceMax > 0) ctx.fillText(fmt((niceMax * k) / 4, 3), cx + 4, cy - (R * k) / 4 + 13);
  }
  for (let g = 0; g < 360; g += 30) {
    const a = (g * Math.PI) / 180;
    ctx.beginPath(); ctx.moveTo(cx, cy); ctx.lineTo(cx + R * Math.sin(a), cy + R * Math.cos(a)); ctx.stroke();
  }
  ctx.fillText('γ 0° (nadir)', cx - 34, cy + R + 18);
  ctx.fillText('180°', cx - 14, cy - R - 8);
  ctx.fillText(planeB.toUpperCase(), 8, 18);
  ctx.textAlign = 'right'; ctx.fillText(planeA.toUpperCase(), W - 8, 18); ctx.textAlign = 'left';
  ctx.fillStyle = '#c7cedb'; ctx.font = '600 13px DejaVu Sans, sans-serif';
  ctx.fillText(title, 8, H - 10);
  if (!(niceMax > 0)) return;
  for (const s of series) {
    ctx.strokeStyle = s.dash ? 'rgba(170,179,197,0.85)' : colour;
    ctx.lineWidth = s.dash ? 1.6 : 2.2;
    ctx.setLineDash(s.dash ? [7, 5] : []);
    ctx.beginPath();
    // planeA on the right (γ from nadir counter-clockwise up the right), planeB on the left.
    const g = s.c.gamma_deg;
    const a = s.c[planeA] || [], b = s.c[planeB] || [];
    let first = true;
    for (let i = 0; i < g.length; ++i) {
      const r = (R * (a[i] || 0)) / niceMax, t = (g[i] * Math.PI) / 180;
      const x = cx + r * Math.sin(t), y = cy + r * Math.cos(t);
      if (first) { ctx.moveTo(x, y); first = false; } else ctx.lineTo(x, y);
    }
    for (let i = g.length - 1; i >= 0; --i) {
      const r = (R * (b[i] || 0)) / niceMax, t = (g[i] * Math.PI) / 180;
      ctx.lineTo(cx - r * Math.sin(t), cy + r * Math.cos(t));
    }
    ctx.closePath();
    ctx.stroke();
  }
  ctx.setLineDash([]);
}
function niceCeil(v) {
  if (!(v > 0)) return 0;
  const p = Math.pow(10, Math.floor(Math.log10(v)));
  for (const m of [1, 1.25, 1.5, 2, 2.5, 3, 4, 5, 6, 8, 10]) if (m * p >= v) return m * p;
  return 10 * p;
}
function drawCurves() {
  const s = page.state;
  if (!s) return;
  polar('curve-c0', s.curves, s.previous_curves, 'c0', 'c180', '#ffb347', 'C0 – C180');
  polar('curve-c90', s.curves, s.previous_curves, 'c90', 'c270', '#4fb3ff', 'C90 – C270');
  page.drawnCurves = { current: s.curves, previous: s.previous_curves };
}

// ---------- numbers and messages ----------
function showNumbers(s) {
  $('model').textContent = s.model || '—';
  const status = $('status');
  status.className = 'pill ' + (s.status || '');
  status.textContent = s.status || '—';
  $('status-text').textContent = s.status_text || '';
  $('run').textContent = 'run ' + (s.run || '—');
  setNumber('flux', s.flux_lm, fmt(s.flux_lm, 5) + ' lm');
  setNumber('emitted', s.emitted_lm, fmt(s.emitted_lm, 5) + ' lm');
  setNumber('lor', s.lor, Number.isFinite(s.lor) ? (100 * s.lor).toFixed(2) + ' %' : '—');
  setNumber('peak', s.max_cd, fmt(s.max_cd, 4) + ' cd');
  setNumber('peak-at', s.max_gamma_deg,
    Number.isFinite(s.max_c_deg) ? `C ${fmt(s.max_c_deg)}° / γ ${fmt(s.max_gamma_deg)}°` : '—');
  const deg = (v) => (Number.isFinite(v) ? v.toFixed(1) + '°' : '—');
  setNumber('beam0', s.beam_angle_c0_c180_deg, deg(s.beam_angle_c0_c180_deg));
  setNumber('beam90', s.beam_angle_c90_c270_deg, deg(s.beam_angle_c90_c270_deg));
  setNumber('field0', s.field_angle_c0_c180_deg, deg(s.field_angle_c0_c180_deg));
  setNumber('field90', s.field_angle_c90_c270_deg, deg(s.field_angle_c90_c270_deg));
  // A spectral run's colour (state.json "colour"; null for grey models).
  const c = s.colour;
  $('colour-group').hidden = !c;
  if (c) {
    const f = (v, d) => (Number.isFinite(v) ? v.toFixed(d) : '—');
    setNumber('cct', c.cct_k, f(c.cct_k, 0) + ' K');
    setNumber('duv', c.duv, f(c.duv, 4));
    setNumber('cie-xy', c.cie_x, `${f(c.cie_x, 4)}, ${f(c.cie_y, 4)}`);
    setNumber('uv-prime', c.u_prime, `${f(c.u_prime, 4)}, ${f(c.v_prime, 4)}`);
    setNumber('delta-uv', c.delta_uv_max, f(c.delta_uv_max, 4));
  }
  setNumber('error-est', s.estimated_rms_error_pct,
    Number.isFinite(s.estimated_rms_error_pct) ? s.estimated_rms_error_pct.toFixed(3) + ' %' : '—');
  setNumber('target', s.target_error_pct, Number.isFinite(s.target_error_pct) ? s.target_error_pct + ' %' : 'none');
  setNumber('iteration', s.iteration, s.iteration ? `${s.iteration} / ${s.iterations ?? '—'}` : '—');
  setNumber('photons', s.photons, fmtCount(s.photons));
  setNumber('rate', s.photons_per_s, fmtCount(Math.round(s.photons_per_s || 0)) + '/s');
  setNumber('elapsed', s.elapsed_s, fmtTime(s.elapsed_s));
  setNumber('time-left', s.time_left_s, s.status === 'running' ? fmtTime(s.time_left_s) : '—');
  setNumber('latency', s.load_to_preview_s, fmtTime(s.load_to_preview_s));
  const done = s.iterations ? s.iteration / s.iterations : 0;
  let frac = done;
  if (Number.isFinite(s.time_left_s) && Number.isFinite(s.elapsed_s) && s.elapsed_s + s.time_left_s > 0)
    frac = Math.max(done, s.elapsed_s / (s.elapsed_s + s.time_left_s));
  if (s.status === 'finished') frac = 1;
  $('progress').style.width = (100 * Math.min(1, frac)).toFixed(1) + '%';
  const now = performance.now();
  // Iterations shown per second over this run's last 10 s of updates.
  const recent = page.updates.filter((t) => now - t < 10000);
  if (recent.length > 1) page.updateRate = (recent.length - 1) / ((recent[recent.length - 1] - recent[0]) / 1000);
  const rate = page.updateRate;
  setNumber('updates', rate, Number.isFinite(rate) ? rate.toFixed(1) + ' /s' : '—');
}
function showMessages(s) {
  const err = $('last-error');
  if (s.last_error) {
    err.classList.add('shown');
    err.textContent = `${s.last_error.time}: ${s.last_error.message}\nThe page shows the last good result.`;
  } else {
    err.classList.remove('shown');
    err.textContent = '';
  }
  const list = $('findings');
  list.innerHTML = '';
  for (const f of s.findings || []) {
    const li = document.createElement('li');
    const sev = document.createElement('span');
    sev.className = 'sev ' + f.severity;
    sev.textContent = f.severity;
    const body = document.createElement('div');
    body.textContent = f.message + (f.code ? ` [${f.code}]` : '');
    if (f.where) {
      const w = document.createElement('div');
      w.className = 'where';
      w.textContent = f.where;
      body.appendChild(w);
    }
    li.append(sev, body);
    list.appendChild(li);
  }
  $('no-findings').style.display = (s.findings || []).length ? 'none' : '';
}

// ---------- the 3D view ----------
let view = null;
function locate(x, y, z, n) {
  const ax = Math.abs(x), ay = Math.abs(y), az = Math.abs(z);
  let face, a, b;
  if (ax >= ay && ax >= az) {
    if (x > 0) { face = 0; a = z / ax; b = -y / ax; } else { face = 1; a = -z / ax; b = -y / ax; }
  } else if (ay >= az) {
    if (y > 0) { face = 2; a = x / ay; b = -z / ay; } else { face = 3; a = x / ay; b = z / ay; }
  } else if (z > 0) { face = 4; a = -x / az; b = -y / az; } else { face = 5; a = x / az; b = -y / az; }
  const tx = Math.min(n - 1, Math.max(0, Math.floor(((a + 1) / 2) * n)));
  const ty = Math.min(n - 1, Math.max(0, Math.floor(((b + 1) / 2) * n)));
  return (face * n + ty) * n + tx;
}
async function init3d() {
  const msg = $('view3d-msg');
  let THREE, OrbitControls;
  try {
    THREE = await import('three');
    ({ OrbitControls } = await import('three/addons/controls/OrbitControls.js'));
  } catch (e) {
    msg.textContent = '3D view unavailable: three.js is not installed beside gonio (npm install three at build time).';
    return;
  }
  const host = $('view3d');
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({ antialias: true, alpha: true, preserveDrawingBuffer: true });
  } catch (e) {
    msg.textContent = '3D view unavailable: this browser has no WebGL.';
    return;
  }
  msg.remove();
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  host.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(40, 1, 0.01, 100);
  camera.position.set(2.5, -1.5, 2.7);  // from below the horizon: the downward light faces the viewer
  // Drawn on demand (a change of view or of the field), never in a loop: the
  // page must not take CPU from the simulation it shows.
  const controls = new OrbitControls(camera, renderer.domElement);
  const render = () => renderer.render(scene, camera);
  controls.addEventListener('change', render);
  const geometry = new THREE.SphereGeometry(1, 128, 64);
  const unit = geometry.attributes.position.array.slice();
  const colours = new Float32Array(unit.length);
  geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
  const mesh = new THREE.Mesh(geometry, new THREE.MeshBasicMaterial({ vertexColors: true, side: THREE.DoubleSide }));
  scene.add(mesh);
  scene.add(new THREE.AxesHelper(1.35));
  const lum = new THREE.Mesh(new THREE.SphereGeometry(0.05, 16, 8), new THREE.MeshBasicMaterial({ color: 0xdddddd }));
  scene.add(lum);
  const resize = () => {
    const w = host.clientWidth, h = host.clientHeight;
    renderer.setSize(w, h, false);
    renderer.domElement.style.width = '100%';
    renderer.domElement.style.height = '100%';
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
    render();
  };
  window.addEventListener('resize', resize);
  resize();
  view = {
    update() {
      const s = page.state, f = page.field;
      if (!s || !s.field || !f) return;
      const n = s.field.face_size, maxCd = scaleTop(s.field), peak = s.field.max_cd;
      if (f.length !== 6 * n * n) return;
      const scale = scaler(maxCd);
      const pos = geometry.attributes.position.array;
      for (let i = 0; i < unit.length; i += 3) {
        const v = f[locate(unit[i], unit[i + 1], unit[i + 2], n)];
        const c = ramp(scale(v));
        colours[i] = c[0] / 255; colours[i + 1] = c[1] / 255; colours[i + 2] = c[2] / 255;
        const r = page.sphereMode === 'solid' ? Math.max(0.002, peak > 0 ? v / peak : 0) : 1;
        pos[i] = unit[i] * r; pos[i + 1] = unit[i + 1] * r; pos[i + 2] = unit[i + 2] * r;
      }
      geometry.attributes.color.needsUpdate = true;
      geometry.attributes.position.needsUpdate = true;
      geometry.computeBoundingSphere();
      render();
    },
  };
  view.update();
  render();
}

// ---------- data flow ----------
let fetching = false, fetchAgain = false;
async function fetchField() {
  if (fetching) { fetchAgain = true; return; }
  fetching = true;
  try {
    do {
      fetchAgain = false;
      const r = await fetch('/field.f32', { cache: 'no-store' });
      const buf = await r.arrayBuffer();
      if (buf.byteLength > 0) {
        page.field = new Float32Array(buf);
        page.fieldVersion = Number(r.headers.get('X-Gonio-Version'));
        drawCube();
        if (view) view.update();
      }
    } while (fetchAgain);
  } catch (e) {
    // the next event tries again
  } finally {
    fetching = false;
  }
}
// ---------- luminance images ----------
// state.json "luminance_images": per view {c_deg, gamma_deg, max_cd_m2,
// intensity_cd, thumbnail {size, cd_m2}} (the run's --luminance-image
// views; null without). Each thumbnail on the page's ramp, log over three
// decades below the 99th percentile of its lit cells (a bare lamp clips).
function drawLuminance(images) {
  const panel = $('luminance-panel');
  panel.hidden = !images || images.length === 0;
  if (panel.hidden) return;
  const box = $('luminance-images');
  while (box.children.length > images.length) box.removeChild(box.lastChild);
  images.forEach((img, k) => {
    let fig = box.children[k];
    if (!fig) {
      fig = document.createElement('figure');
      fig.appendChild(document.createElement('canvas'));
      fig.appendChild(document.createElement('figcaption'));
      box.appendChild(fig);
    }
    const t = img.thumbnail || {size: 0, cd_m2: []};
    const canvas = fig.firstChild;
    const px = Math.max(1, Math.floor(192 / Math.max(1, t.size)));
    canvas.width = canvas.height = t.size * px;
    const ctx = canvas.getContext('2d');
    ctx.fillStyle = 'rgb(12,14,26)';
    ctx.fillRect(0, 0, canvas.width, canvas.height);
    const lit = t.cd_m2.filter((v) => v > 0).sort((a, b) => a - b);
    const top = lit.length ? lit[Math.floor(0.99 * (lit.length - 1))] : 0;
    for (let y = 0; y < t.size; ++y)
      for (let x = 0; x < t.size; ++x) {
        const v = t.cd_m2[y * t.size + x];
        if (!(v > 0) || !(top > 0)) continue;
        const c = ramp(1 + Math.log10(v / top) / 3);
        ctx.fillStyle = `rgb(${c[0] | 0},${c[1] | 0},${c[2] | 0})`;
        ctx.fillRect(x * px, y * px, px, px);
      }
    fig.lastChild.textContent = `C ${fmt(img.c_deg)}° γ ${fmt(img.gamma_deg)}°: max ${fmtCount(Math.round(img.max_cd_m2 || 0))} cd/m², ` +
      `${Number.isFinite(img.intensity_cd) ? img.intensity_cd.toFixed(1) : '—'} cd`;
  });
}

// ---------- an optimisation (gonio watch DIR: state.json of gonio optimize) ----------
// state.kind "optimize": the best so far (curves) against the target
// (previous_curves, dashed), and the merit of every evaluation
// (optimize.history: history.json's rows) with the best so far, log scale.
function drawMeritHistory(history) {
  const canvas = $('merit-history'), ctx = canvas.getContext('2d');
  const W = canvas.width, H = canvas.height;
  ctx.clearRect(0, 0, W, H);
  const rows = (history || []).filter((r) => Number.isFinite(r.merit) && r.merit > 0);
  page.drawnHistory = rows.length;
  if (!rows.length) return;
  let lo = Infinity, hi = 0, last = 1;
  for (const r of rows) {
    lo = Math.min(lo, r.merit, Number.isFinite(r.best) && r.best > 0 ? r.best : r.merit);
    hi = Math.max(hi, r.merit);
    last = Math.max(last, r.index);
  }
  const l0 = Math.floor(Math.log10(lo)), l1 = Math.max(l0 + 1, Math.ceil(Math.log10(hi)));
  const L = 56, R = W - 12, T = 10, B = H - 28;
  const x = (i) => L + ((R - L) * (i - 1)) / Math.max(1, last - 1);
  const y = (v) => B - ((B - T) * (Math.log10(v) - l0)) / (l1 - l0);
  ctx.strokeStyle = '#2b3240'; ctx.fillStyle = '#7d879a'; ctx.font = '12px DejaVu Sans, sans-serif';
  for (let k = l0; k <= l1; ++k) {
    ctx.beginPath(); ctx.moveTo(L, y(10 ** k)); ctx.lineTo(R, y(10 ** k)); ctx.stroke();
    ctx.fillText(fmt(10 ** k, 2), 4, y(10 ** k) + 4);
  }
  ctx.fillText('evaluation', R - 60, H - 8);
  ctx.fillText('1', L - 3, H - 12);
  ctx.fillText(String(last), R - 20, H - 12);
  for (const r of rows) {
    ctx.fillStyle = r.stage === 'noise' ? '#ffb347' : 'rgba(170,179,197,0.8)';
    ctx.beginPath(); ctx.arc(x(r.index), y(r.merit), r.stage === 'noise' ? 3.5 : 2.2, 0, 2 * Math.PI); ctx.fill();
  }
  ctx.strokeStyle = '#43c59e'; ctx.lineWidth = 2; ctx.beginPath();
  let first = true;
  for (const r of rows) {
    if (r.stage === 'noise' || !(r.best > 0)) continue;
    if (first) { ctx.moveTo(x(r.index), y(r.best)); first = false; } else ctx.lineTo(x(r.index), y(r.best));
  }
  ctx.stroke(); ctx.lineWidth = 1;
}
function showOptimize(s) {
  const opt = s.kind === 'optimize';
  document.querySelector('main').classList.toggle('optimize', opt);
  $('optimize-panel').hidden = !opt;
  $('cube-panel').hidden = opt;
  $('sphere-panel').hidden = opt;
  for (const el of document.querySelectorAll('.cur-label')) el.textContent = opt ? 'best so far' : 'this run';
  $('prev-label').textContent = opt ? 'target' : 'previous run';
  $('curves-title').textContent = opt ? 'Polar curves (cd) — the best so far against the target, at the merit\'s nodes'
                                      : 'Polar curves (cd) — filtered';
  if (!opt) return;
  const o = s.optimize || {};
  $('opt-method').textContent = o.method || '—';
  setNumber('opt-best', o.best_merit, fmt(o.best_merit, 5));
  setNumber('opt-start', o.start_merit, fmt(o.start_merit, 5));
  setNumber('opt-rms', o.candela_rms_pct, Number.isFinite(o.candela_rms_pct) ? o.candela_rms_pct.toFixed(3) + ' %' : '—');
  const deg = (v) => (Number.isFinite(v) ? v.toFixed(1) + '°' : '—');
  setNumber('opt-beam', o.beam_angle_deg, `${deg(o.beam_angle_deg)} / ${deg(o.target_beam_angle_deg)}`);
  setNumber('opt-evaluation', o.evaluation, o.evaluation ? `${o.evaluation} / ${o.max_evals ?? '—'}` : '—');
  setNumber('opt-stage', o.stage, o.stage ?? '—');
  setNumber('opt-best-index', o.best_index, o.best_index ?? '—');
  setNumber('opt-noise', o.noise_floor, fmt(o.noise_floor, 3));
  const fin = o.final || {};
  setNumber('opt-final', fin.candela_rms_pct, Number.isFinite(fin.candela_rms_pct) ? fin.candela_rms_pct.toFixed(3) + ' %' : '—');
  const vars = $('opt-variables');
  vars.innerHTML = '';
  for (const [name, v] of Object.entries(o.best_values || {})) {
    const dt = document.createElement('dt'), dd = document.createElement('dd');
    dt.textContent = name;
    dd.textContent = fmt(v, 6);
    dd.dataset.value = String(v);
    vars.append(dt, dd);
  }
  drawMeritHistory(o.history);
}

function onState(s) {
  const newIteration = !page.state || s.iteration !== page.state.iteration || s.run !== page.state.run;
  if (page.state && s.run !== page.state.run) page.updates = [];  // the rate of this run alone
  page.state = s;
  if (newIteration && s.iteration) page.updates.push(performance.now());
  if (page.updates.length > 200) page.updates.splice(0, 100);
  showNumbers(s);
  showOptimize(s);
  showMessages(s);
  drawCurves();
  drawLuminance(s.luminance_images);
  if (s.field && s.field.version > page.fieldVersion) fetchField();
}
function connect() {
  const conn = $('conn');
  const es = new EventSource('/events');
  es.onopen = () => { conn.className = ''; conn.title = 'connected'; };
  es.onmessage = (ev) => onState(JSON.parse(ev.data));
  es.onerror = () => { conn.className = 'lost'; conn.title = 'connection lost: retrying'; };
}
function toggles(id, key, redraw) {
  for (const b of $(id).querySelectorAll('button')) {
    b.addEventListener('click', () => {
      page[key] = b.dataset.v;
      for (const o of $(id).querySelectorAll('button')) o.classList.toggle('on', o === b);
      redraw();
    });
  }
}
toggles('cube-scale', 'cubeScale', () => { drawCube(); if (view) view.update(); });
toggles('sphere-mode', 'sphereMode', () => { if (view) view.update(); });
connect();
init3d();
