// Drives `gonio watch DIR` on a running `gonio optimize --out DIR` in a real
// headless Chromium (puppeteer-core): see watch_browser_test.cpp. The page,
// opened before the optimisation starts, shows it waiting, then the
// optimisation panel (no cube, no sphere) with the merit history drawn while
// the run goes on, and once finished the best merit, the final trace's RMS,
// the best variable, the history's rows and the curves as report.json,
// history.json and GET /state.json give them. Prints one JSON line on
// success; throws (exit 1) with the reason.
//
// node watch_optimize_page.mjs PUPPETEER_DIR CHROMIUM GONIO WORK_DIR ARTIFACTS_DIR
import { spawn, spawnSync } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';

const [puppeteerDir, chromium, gonio, work, artifacts] = process.argv.slice(2);
const require = createRequire(path.resolve(puppeteerDir, 'package.json'));
const puppeteer = require('puppeteer-core');

function check(cond, message) {
  if (!cond) throw new Error(message);
}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// The conic dish of tests/tools/cli/cmd_optimize_test.cpp: a point source of
// 1000 lm shining up (318.31 cd · −cos γ above 90°), written as IES LM-63.
function writeCase() {
  const g = [], cd = [];
  for (let i = 0; i <= 72; ++i) {
    g.push(2.5 * i);
    cd.push(g[i] <= 90 ? 0 : -318.31 * Math.cos((g[i] * Math.PI) / 180));
  }
  fs.writeFileSync(path.join(work, 'up.ies'), ['IESNA:LM-63-2002', 'TILT=NONE', '1 1000 1 73 1 1 2 0 0 0', '1 1 0',
    g.join(' '), '0', cd.map((v) => v.toFixed(3)).join(' '), ''].join('\n'));
  const design = (conic) => ['length_unit = "mm"', '[materials.mirror]', 'reflectance = 0.9', '[[emitters]]',
    'name = "LED"', 'position = [0, 0, 0]', 'profile = "up.ies"', '[[reflectors]]', 'name = "dish"',
    'material = "mirror"', 'profile = "conic"', 'radius = 10', `conic = ${conic}`, 'vertex = 5',
    'aperture = [2, 30]', ''].join('\n');
  fs.writeFileSync(path.join(work, 'truth.design.toml'), design('-1.5'));
  fs.writeFileSync(path.join(work, 'start.design.toml'), design('{ value = -2.6, min = -3, max = -1 }'));
  const t = spawnSync(gonio, ['simulate', path.join(work, 'truth.design.toml'), '--out', path.join(work, 'truth'),
    '--photons', '200000', '--iterations', '1', '--gamma-step', '2.5', '--format', 'ies', '--no-cache']);
  check(t.status === 0, 'the target did not simulate: ' + t.stderr);
}

let watch = null, browser = null;
try {
  writeCase();
  const out = path.join(work, 'out');
  fs.mkdirSync(out, { recursive: true });
  watch = spawn(gonio, ['watch', out, '--port', '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
  let stdout = '';
  watch.stdout.on('data', (d) => { stdout += d; });
  watch.stderr.on('data', () => {});
  let url = null;
  for (let i = 0; i < 200 && !url; ++i) {
    const m = stdout.match(/live page: (\S+)/);
    if (m) url = m[1]; else await sleep(100);
  }
  check(url, 'gonio watch DIR printed no live page URL: ' + stdout);
  browser = await puppeteer.launch({
    executablePath: chromium,
    headless: true,
    userDataDir: path.join(work, 'chromium-profile'),
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
      '--disable-component-update', '--disable-sync', '--no-first-run', '--window-size=1500,1100'],
  });
  const page = await browser.newPage();
  await page.setViewport({ width: 1500, height: 1100 });
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(String(e)));
  await page.goto(url, { waitUntil: 'load' });
  await page.waitForFunction(() => window.gonioPage.state && window.gonioPage.state.status === 'loading',
    { timeout: 20000 });
  check(await page.evaluate(() => !document.getElementById('optimize-panel').hidden),
    'the optimisation panel is hidden while waiting');

  const run = spawn(gonio, ['optimize', path.join(work, 'start.design.toml'), '--target',
    path.join(work, 'truth', 'truth.ies'), '--out', out, '--gamma-step', '5', '--no-step', '--max-evals', '40',
    '--final-photons', '100000', '--threads', '1'], { stdio: ['ignore', 'ignore', 'pipe'] });
  let runErr = '', runExit = null;
  run.stderr.on('data', (d) => { runErr += d; });
  run.on('exit', (code) => { runExit = code; });
  // While it runs: the panel with a history drawn and a best merit shown.
  await page.waitForFunction(() => window.gonioPage.state.status === 'running' && window.gonioPage.drawnHistory >= 3,
    { timeout: 120000 });
  const during = await page.evaluate(() => ({
    best: Number(document.getElementById('opt-best').dataset.value),
    drawn: window.gonioPage.drawnHistory,
    stateBest: window.gonioPage.state.optimize.best_merit,
    cube: document.getElementById('cube-panel').hidden,
    sphere: document.getElementById('sphere-panel').hidden,
    prev: document.getElementById('prev-label').textContent,
  }));
  check(during.best === during.stateBest, `the page shows best ${during.best}, the state ${during.stateBest}`);
  check(during.cube && during.sphere, 'the cube and the sphere show for an optimisation');
  check(during.prev === 'target', 'the dashed curve is not labelled the target: ' + during.prev);
  await page.screenshot({ path: path.join(artifacts, 'watch-optimize-running.png') });
  await page.waitForFunction(() => window.gonioPage.state.status === 'finished', { timeout: 240000 });
  for (let i = 0; i < 600 && runExit === null; ++i) await sleep(100);
  check(runExit === 0, `gonio optimize exited ${runExit}: ${runErr}`);

  const report = JSON.parse(fs.readFileSync(path.join(out, 'report.json'), 'utf8')).optimize;
  const history = JSON.parse(fs.readFileSync(path.join(out, 'history.json'), 'utf8'));
  const state = await (await fetch(url + 'state.json')).json();
  const shown = await page.evaluate(() => ({
    best: Number(document.getElementById('opt-best').dataset.value),
    final: Number(document.getElementById('opt-final').dataset.value),
    noise: Number(document.getElementById('opt-noise').dataset.value),
    variable: Number(document.querySelector('#opt-variables dd').dataset.value),
    drawn: window.gonioPage.drawnHistory,
    curves: window.gonioPage.drawnCurves,
  }));
  check(shown.best === report.best_merit, `best merit ${shown.best} on the page, ${report.best_merit} in report.json`);
  check(shown.final === report.final.candela_rms_pct,
    `final RMS ${shown.final} on the page, ${report.final.candela_rms_pct} in report.json`);
  check(shown.noise === report.noise_floor, `noise floor ${shown.noise} on the page, ${report.noise_floor} in report.json`);
  check(shown.variable === report.variables[0].best,
    `best conic ${shown.variable} on the page, ${report.variables[0].best} in report.json`);
  check(shown.drawn === history.filter((r) => Number.isFinite(r.merit) && r.merit > 0).length,
    `${shown.drawn} evaluations drawn, ${history.length} in history.json`);
  check(JSON.stringify(shown.curves.current) === JSON.stringify(state.curves), 'the drawn best curves are not the state\'s');
  check(JSON.stringify(shown.curves.previous) === JSON.stringify(state.previous_curves),
    'the drawn target curves are not the state\'s');
  check(pageErrors.length === 0, 'errors on the page: ' + pageErrors.join('; '));
  await page.screenshot({ path: path.join(artifacts, 'watch-optimize.png') });
  console.log(JSON.stringify({ evaluations: history.length, drawn_while_running: during.drawn,
    best_merit: report.best_merit, final_rms_pct: report.final.candela_rms_pct }));
} finally {
  if (browser) await browser.close();
  if (watch && watch.exitCode === null) watch.kill('SIGINT');
}
