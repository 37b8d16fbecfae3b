// Latency of the interactive loop, measured in a real browser: from saving a
// model to the first filtered preview of the new model drawn on `gonio
// watch`'s page, and the page's update rate while a run goes on. Not a test
// (timings depend on the machine); run it by hand, on a quiet machine for
// figures to quote:
//
//   node benchmarks/watch_latency.mjs PUPPETEER_DIR CHROMIUM GONIO MODEL.gltf [REPEATS]
//
// PUPPETEER_DIR: a puppeteer-core install (the browser test puts one in
// build/browser/node_modules/puppeteer-core). The model is copied to a
// temporary folder with its files; each repeat moves the first mesh node by
// 1 mm and back while watch runs (1 M photons per iteration, endless), and
// waits until the page shows the new run's first preview with its field.
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { createRequire } from 'node:module';

const [puppeteerDir, chromium, gonio, model, repeatsArg] = process.argv.slice(2);
const repeats = Number(repeatsArg || 5);
const require = createRequire(path.resolve(puppeteerDir, 'package.json'));
const puppeteer = require('puppeteer-core');
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

const work = fs.mkdtempSync(path.join(os.tmpdir(), 'gonio-latency-'));
const gltf = JSON.parse(fs.readFileSync(model, 'utf8'));
for (const b of gltf.buffers || []) if (b.uri && !b.uri.startsWith('data:'))
  fs.copyFileSync(path.join(path.dirname(model), b.uri), path.join(work, b.uri));
const target = path.join(work, path.basename(model));
fs.writeFileSync(target, JSON.stringify(gltf));
const node = gltf.nodes.find((n) => n.mesh !== undefined);

const proc = spawn(gonio, ['watch', target, '--port', '0', '--iterations', '100000'], { stdio: ['ignore', 'pipe', 'inherit'] });
let out = '';
proc.stdout.on('data', (d) => { out += d; });
let url = null;
for (let i = 0; i < 200 && !url; ++i) { const m = out.match(/live page: (\S+)/); if (m) url = m[1]; else await sleep(100); }
const browser = await puppeteer.launch({ executablePath: chromium, headless: true,
  userDataDir: path.join(work, 'profile'),
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking', '--disable-component-update',
    '--disable-sync', '--no-first-run', '--enable-unsafe-swiftshader'] });
const page = await browser.newPage();
await page.goto(url);
await page.waitForFunction(() => window.gonioPage.state && window.gonioPage.state.iteration >= 2, { timeout: 120000 });
const latencies = [], server = [];
for (let k = 0; k < repeats; ++k) {
  await sleep(1500);  // mid-run, as a designer saves while it traces
  const run = await page.evaluate(() => window.gonioPage.state.run);
  const t = node.translation || [0, 0, 0];
  node.translation = [t[0], t[1] + (k % 2 ? -0.001 : 0.001), t[2]];
  const t0 = Date.now();
  fs.writeFileSync(target, JSON.stringify(gltf));
  await page.waitForFunction((r) => {
    const p = window.gonioPage;
    return p.state.run === r + 1 && p.state.iteration >= 1 && p.fieldVersion >= p.state.field.version;
  }, { timeout: 60000, polling: 5 }, run);
  latencies.push((Date.now() - t0) / 1000);
  server.push(await page.evaluate(() => window.gonioPage.state.load_to_preview_s));
}
await sleep(5000);
const rate = await page.evaluate(() => window.gonioPage.updateRate);
const pps = await page.evaluate(() => window.gonioPage.state.photons_per_s);
await browser.close();
proc.kill('SIGINT');
const sorted = [...latencies].sort((a, b) => a - b);
console.log(JSON.stringify({ model: path.basename(model), save_to_page_s: latencies, median_s: sorted[sorted.length >> 1],
  server_change_to_preview_s: server, page_updates_per_s: rate, photons_per_s: pps }));
