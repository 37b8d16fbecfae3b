// Drives `gonio watch` and its live page in a real headless Chromium
// (puppeteer-core): see watch_browser_test.cpp for what it checks. Prints one
// JSON line of measurements on success; throws (exit 1) with the reason.
//
// node watch_page.mjs PUPPETEER_DIR CHROMIUM GONIO SAMPLES_DIR WORK_DIR ARTIFACTS_DIR
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';

const [puppeteerDir, chromium, gonio, samplesDir, work, artifacts] = process.argv.slice(2);
const require = createRequire(path.resolve(puppeteerDir, 'package.json'));
const puppeteer = require('puppeteer-core');

function check(cond, message) {
  if (!cond) throw new Error(message);
}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
// Starts one more `gonio watch ARGS…`: url() waits for its live page's
// address (null after 20 s), stop() ends it (SIGINT, then SIGKILL) and gives
// its exit code.
function startWatch(args) {
  const w = spawn(gonio, ['watch', ...args], { stdio: ['ignore', 'pipe', 'pipe'] });
  let out = '';
  let exit = null;
  w.stdout.on('data', (d) => { out += d; });
  w.stderr.on('data', () => {});
  w.on('exit', (code) => { exit = code; });
  return {
    async url() {
      for (let i = 0; i < 200; ++i) {
        const m = out.match(/live page: (\S+)/);
        if (m) return m[1];
        await sleep(100);
      }
      return null;
    },
    async stop() {
      if (exit === null) w.kill('SIGINT');
      for (let i = 0; i < 100 && exit === null; ++i) await sleep(50);
      if (exit === null) w.kill('SIGKILL');
      return exit;
    },
  };
}

// A .glb from a .gltf with one external buffer: JSON chunk + BIN chunk.
function packGlb(gltf, bin) {
  const g = structuredClone(gltf);
  g.buffers = [{ byteLength: bin.length }];
  let json = Buffer.from(JSON.stringify(g));
  json = Buffer.concat([json, Buffer.alloc((4 - (json.length % 4)) % 4, 0x20)]);
  const binPadded = Buffer.concat([bin, Buffer.alloc((4 - (bin.length % 4)) % 4, 0)]);
  const header = Buffer.alloc(12);
  header.write('glTF', 0);
  header.writeUInt32LE(2, 4);
  header.writeUInt32LE(12 + 8 + json.length + 8 + binPadded.length, 8);
  const chunk = (type, data) => {
    const h = Buffer.alloc(8);
    h.writeUInt32LE(data.length, 0);
    h.write(type, 4);
    return Buffer.concat([h, data]);
  };
  return Buffer.concat([header, chunk('JSON', json), chunk('BIN\0', binPadded)]);
}

const bellDir = path.join(samplesDir, 'bell');
const gltf = JSON.parse(fs.readFileSync(path.join(bellDir, 'bell.gltf'), 'utf8'));
const bin = fs.readFileSync(path.join(bellDir, gltf.buffers[0].uri));
const model = path.join(work, 'bell.glb');
const outDir = path.join(work, 'out');
fs.writeFileSync(model, packGlb(gltf, bin));

// The shade (the bell's reflector) moved up by `dy` metres; with `typo`, an
// unknown key in the scene's extras.gonio (a warning finding).
function moved(dy, typo = false) {
  const g = structuredClone(gltf);
  if (typo) {
    const sc = g.scenes[g.scene || 0];
    sc.extras = sc.extras || {};
    sc.extras.gonio = { ...(sc.extras.gonio || {}), fram: 1 };
  }
  const shade = g.nodes.find((n) => n.name === 'shade');
  check(shade, 'the bell sample has no node named shade');
  const t = shade.translation || [0, 0, 0];
  shade.translation = [t[0], t[1] + dy, t[2]];
  return packGlb(g, bin);
}

const proc = spawn(gonio, ['watch', model, '--port', '0', '--photons', '100000', '--iterations', '4',
  '--out', outDir], { stdio: ['ignore', 'pipe', 'pipe'] });
let stdout = '', stderr = '';
proc.stdout.on('data', (d) => { stdout += d; });
proc.stderr.on('data', (d) => { stderr += d; });
let exited = null;
proc.on('exit', (code, signal) => { exited = { code, signal }; });

let browser = null;
const result = {};
try {
  let url = null;
  for (let i = 0; i < 200 && !url; ++i) {
    const m = stdout.match(/live page: (http:\/\/127\.0\.0\.1:\d+\/)/);
    if (m) url = m[1];
    else if (exited) throw new Error(`gonio watch exited: ${JSON.stringify(exited)}\n${stderr}`);
    else await sleep(100);
  }
  check(url, 'gonio watch printed no live page URL: ' + stdout + stderr);
  const stateJson = async () => (await fetch(url + 'state.json')).json();

  browser = await puppeteer.launch({
    executablePath: chromium,
    headless: true,
    userDataDir: path.join(work, 'chromium-profile'),
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
      '--disable-component-update', '--disable-sync', '--no-first-run', '--window-size=1500,1100',
      // software WebGL (SwiftShader) for the 3D view: no GPU here
      '--enable-unsafe-swiftshader'],
  });
  const page = await browser.newPage();
  await page.setViewport({ width: 1500, height: 1100 });
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(String(e)));
  await page.goto(url, { waitUntil: 'load' });

  // 1. Two iterations arrive without reloading.
  await page.waitForFunction(() => window.gonioPage.state && window.gonioPage.state.run === 1 &&
    window.gonioPage.state.iteration >= 2, { timeout: 60000 });
  // 2. The run finishes; watch --out writes report.json; the page's numbers are the report's.
  await page.waitForFunction(() => window.gonioPage.state.status === 'finished', { timeout: 120000 });
  for (let i = 0; i < 100 && !fs.existsSync(path.join(outDir, 'report.json')); ++i) await sleep(100);
  const report = JSON.parse(fs.readFileSync(path.join(outDir, 'report.json'), 'utf8'));
  const shown = await page.evaluate(() => {
    const v = (id) => Number(document.getElementById(id).dataset.value);
    return { flux: v('flux'), emitted: v('emitted'), lor: v('lor'), photons: v('photons'), error: v('error-est'),
      peak: v('peak'), beam0: v('beam0'), iteration: v('iteration'),
      fluxText: document.getElementById('flux').textContent, fieldVersion: window.gonioPage.fieldVersion };
  });
  const close = (a, b, what) => check(Math.abs(a - b) <= 1e-9 * Math.max(1, Math.abs(b)),
    `${what}: the page shows ${a}, expected ${b}`);
  close(shown.flux, report.escaped_lm, 'flux vs report.json escaped_lm');
  close(shown.emitted, report.emitted_lm, 'emitted flux vs report.json');
  close(shown.lor, report.energy.lor, 'LOR vs report.json energy.lor');
  close(shown.photons, report.photons_emitted, 'photons vs report.json');
  close(shown.iteration, report.iterations_done, 'iteration vs report.json iterations_done');
  check(report.stopped_by === 'iterations', 'report.json stopped_by ' + report.stopped_by);
  const state1 = await stateJson();
  close(shown.error, state1.estimated_rms_error_pct, 'estimated error vs state.json');
  close(shown.peak, state1.max_cd, 'peak vs state.json');
  close(shown.beam0, state1.beam_angle_c0_c180_deg, 'beam angle vs state.json');
  close(state1.flux_lm, report.escaped_lm, 'state.json flux_lm vs report.json');
  check(shown.fluxText.includes('lm'), 'flux shown without its unit: ' + shown.fluxText);
  check(shown.fieldVersion > 0, 'the page never fetched the field');
  // A grey model: no colour on the page.
  check(state1.colour === null, 'a grey model has colour in state.json');
  check(await page.evaluate(() => document.getElementById('colour-group').hidden), 'the colour group shows for a grey model');
  result.photons_per_s = state1.photons_per_s;
  // The cube canvas has content (not one flat colour).
  const cubeColours = await page.evaluate(() => {
    const c = document.getElementById('cube');
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    const seen = new Set();
    for (let i = 0; i < d.length; i += 4 * 97) seen.add(`${d[i]},${d[i + 1]},${d[i + 2]}`);
    return seen.size;
  });
  check(cubeColours > 20, `the unfolded cube is nearly flat (${cubeColours} colours)`);
  const curves1 = await page.evaluate(() => window.gonioPage.drawnCurves.current);
  await page.screenshot({ path: path.join(artifacts, 'watch-page-run1.png') });

  // 3. The reflector moves: a new run starts, its curves differ, the old ones stay dashed.
  const changedAt = Date.now();
  fs.writeFileSync(model, moved(0.2));
  await page.waitForFunction(() => window.gonioPage.state.run === 2 && window.gonioPage.state.iteration >= 1 &&
    window.gonioPage.fieldVersion >= window.gonioPage.state.field.version, { timeout: 60000, polling: 10 });
  result.save_to_first_preview_s = (Date.now() - changedAt) / 1000;
  const run2 = await page.evaluate(() => ({ s: window.gonioPage.state, drawn: window.gonioPage.drawnCurves }));
  result.server_load_to_preview_s = run2.s.load_to_preview_s;
  check(JSON.stringify(run2.drawn.previous.c0) === JSON.stringify(curves1.c0),
    'the previous run\'s curves are not the first run\'s');
  const nadir1 = curves1.c0[0], nadir2 = run2.drawn.current.c0[0];
  check(Math.abs(nadir2 - nadir1) > 0.2 * nadir1,
    `moving the shade did not change the nadir intensity (${nadir1} → ${nadir2} cd)`);
  // Let it iterate a little, then count the page's update rate.
  await page.waitForFunction(() => window.gonioPage.state.status === 'finished', { timeout: 120000 });
  const updates = await page.evaluate(() => window.gonioPage.updates.slice());
  result.page_updates = updates.length;
  result.page_update_rate_per_s = await page.evaluate(() => window.gonioPage.updateRate);
  await page.screenshot({ path: path.join(artifacts, 'watch-page.png') });

  // 4. A truncated .glb: the error shows, the server stays up, the last good result stays.
  const lastGoodFlux = await page.evaluate(() => Number(document.getElementById('flux').dataset.value));
  const whole = moved(0.1);
  fs.writeFileSync(model, whole.subarray(0, Math.floor(whole.length / 2)));
  await page.waitForFunction(() => window.gonioPage.state.status === 'error' &&
    document.getElementById('last-error').classList.contains('shown'), { timeout: 30000 });
  const errorText = await page.evaluate(() => document.getElementById('last-error').textContent);
  check(errorText.includes('bell.glb'), 'the error does not name the model: ' + errorText);
  const state3 = await stateJson();
  check(state3.last_error && state3.last_error.message.includes('bell.glb'), 'state.json has no last_error');
  check(state3.run === 2 && state3.flux_lm === lastGoodFlux, 'the last good result did not stay up');
  check(exited === null, 'gonio watch died on a truncated model');
  await page.screenshot({ path: path.join(artifacts, 'watch-page-error.png') });
  result.error_text = errorText.split('\n')[0];

  // 5. A good model again, with a typo in its extras: it recovers, and the
  //    reader's warning is on the page.
  fs.writeFileSync(model, moved(0.1, true));
  await page.waitForFunction(() => window.gonioPage.state.run === 3 && window.gonioPage.state.iteration >= 1 &&
    !window.gonioPage.state.last_error, { timeout: 60000 });
  const findings = await page.evaluate(() => [...document.querySelectorAll('#findings li')].map((li) => li.textContent));
  check(findings.some((f) => f.includes('warning') && f.includes('fram')),
    'the model\'s warning is not among the page\'s findings: ' + JSON.stringify(findings));
  check(!(await page.evaluate(() => document.getElementById('last-error').classList.contains('shown'))),
    'the error is still shown after the model was repaired');
  await page.screenshot({ path: path.join(artifacts, 'watch-page-findings.png'), fullPage: true });
  check(pageErrors.length === 0, 'errors in the page: ' + pageErrors.join('; '));
} finally {
  if (browser) await browser.close();
  if (exited === null) {
    proc.kill('SIGINT');
    for (let i = 0; i < 100 && exited === null; ++i) await sleep(50);
  }
  if (exited === null) proc.kill('SIGKILL');
}
check(exited && exited.code === 0, `gonio watch did not end cleanly on Ctrl-C: ${JSON.stringify(exited)}\n${stderr}`);
check(stdout.includes('watch: stopped'), 'gonio watch did not say it stopped: ' + stdout);

// 6. A profile the model references changes (the downlight's led.ies, its
//    bytes rewritten): a new run, followed through GET /state.json alone.
{
  const dir = path.join(work, 'downlight');
  fs.mkdirSync(dir);
  for (const f of fs.readdirSync(path.join(samplesDir, 'downlight')))
    fs.copyFileSync(path.join(samplesDir, 'downlight', f), path.join(dir, f));
  const w = startWatch([path.join(dir, 'downlight.gltf'), '--port', '0', '--photons', '50000']);
  let wexit = null;
  try {
    const wurl = await w.url();
    check(wurl, 'the second gonio watch printed no URL');
    const state = async () => (await fetch(wurl + 'state.json')).json();
    let s = await state();
    for (let i = 0; i < 600 && !(s.run === 1 && s.iteration >= 1); ++i) { await sleep(100); s = await state(); }
    check(s.run === 1 && s.iteration >= 1, 'the downlight never ran: ' + JSON.stringify(s).slice(0, 300));
    check(s.bvh_reused === false, 'the first run says it reused a BVH');
    const ies = path.join(dir, 'led.ies');
    fs.writeFileSync(ies, fs.readFileSync(ies));
    for (let i = 0; i < 600 && !(s.run >= 2 && s.iteration >= 1); ++i) { await sleep(100); s = await state(); }
    check(s.run === 2, 'rewriting the referenced profile led.ies started no new run');
    // The geometry did not change: the first run's BVH serves the second.
    check(s.bvh_reused === true && s.bvh_s < 0.05, 'the unchanged geometry was built again: ' + s.bvh_reused + ' ' + s.bvh_s);
    result.profile_change = 'restarted';
  } finally {
    wexit = await w.stop();
  }
  check(wexit === 0, 'the second gonio watch did not end cleanly: ' + wexit);
}
// 7. A spectral model (the bell's lamp a 2856 K blackbody, every surface
//    grey): the page shows its colour as state.json and report.json give it,
//    and the CCT is the blackbody's (grey paths add no colour noise).
{
  const dir = path.join(work, 'spectral');
  fs.mkdirSync(dir);
  const g = structuredClone(gltf);
  const light = g.extensions.KHR_lights_punctual.lights[0];
  light.extras = { gonio: { spectrum: { blackbody_k: 2856 } } };
  const sm = path.join(dir, 'bell-2856.glb');
  fs.writeFileSync(sm, packGlb(g, bin));
  const sout = path.join(dir, 'out');
  const w = startWatch([sm, '--port', '0', '--photons', '50000', '--iterations', '2', '--out', sout]);
  let wexit = null;
  let b = null;
  try {
    const wurl = await w.url();
    check(wurl, 'the spectral gonio watch printed no URL');
    b = await puppeteer.launch({ executablePath: chromium, headless: true,
      userDataDir: path.join(work, 'chromium-profile-2'),
      args: ['--headless', '--no-sandbox', '--disable-gpu', '--no-first-run', '--window-size=1500,1100',
        '--enable-unsafe-swiftshader'] });
    const page = await b.newPage();
    await page.setViewport({ width: 1500, height: 1100 });
    await page.goto(wurl, { waitUntil: 'load' });
    await page.waitForFunction(() => window.gonioPage.state && window.gonioPage.state.status === 'finished',
      { timeout: 120000 });
    for (let i = 0; i < 100 && !fs.existsSync(path.join(sout, 'report.json')); ++i) await sleep(100);
    const report = JSON.parse(fs.readFileSync(path.join(sout, 'report.json'), 'utf8'));
    const s = await (await fetch(wurl + 'state.json')).json();
    check(s.colour, 'state.json has no colour for a spectral model');
    const shown = await page.evaluate(() => {
      const v = (id) => Number(document.getElementById(id).dataset.value);
      return { hidden: document.getElementById('colour-group').hidden, cct: v('cct'), duv: v('duv'),
        x: v('cie-xy'), u: v('uv-prime'), delta: v('delta-uv'), cctText: document.getElementById('cct').textContent };
    });
    check(!shown.hidden, 'the colour group is hidden for a spectral model');
    const same = (a, b, what) => check(Math.abs(a - b) <= 1e-9 * Math.max(1, Math.abs(b)), `${what}: ${a} against ${b}`);
    same(shown.cct, s.colour.cct_k, 'CCT on the page vs state.json');
    same(shown.duv, s.colour.duv, 'Duv on the page vs state.json');
    same(shown.x, s.colour.cie_x, 'x on the page vs state.json');
    same(shown.u, s.colour.u_prime, "u' on the page vs state.json");
    same(shown.delta, s.colour.delta_uv_max, "delta u'v' max on the page vs state.json");
    // The same photons and the same grid as the report's.
    same(s.colour.cct_k, report.colour.cct_k, 'state.json CCT vs report.json');
    same(s.colour.delta_uv_max, report.colour_over_angle.delta_uv_max, "state.json delta u'v' max vs report.json");
    check(Math.abs(shown.cct - 2856) < 1, 'the bare blackbody lamp behind grey surfaces shows CCT ' + shown.cct);
    check(shown.cctText.endsWith(' K'), 'CCT shown without its unit: ' + shown.cctText);
    await page.screenshot({ path: path.join(artifacts, 'watch-page-colour.png') });
    result.colour_cct_k = shown.cct;
  } finally {
    if (b) await b.close();
    wexit = await w.stop();
  }
  check(wexit === 0, 'the spectral gonio watch did not end cleanly: ' + wexit);
}
console.log(JSON.stringify(result));
