// A screenshot of the page of `vmas edit` on INPUT, as the README shows it
// (scripts/figures/vmas-edit.png):
//
//   node tests/browser/screenshot.mjs INPUT OUT.png [--orbit DX,DY] [--click X,Y] [--hover X,Y]
//                                     [--keys KEYS] [--settle SECONDS] [-- VMAS_EDIT_OPTIONS...]
//   e.g. (the README's) node tests/browser/screenshot.mjs ../shared/data/meshes/armadillo.off \
//          scripts/figures/vmas-edit.png --orbit 400,0 --hover 735,450 -- --spheres 40 --threads 2
//
// Runs vmas edit (VMAS_BINARY, default build/vmas) with the options after --, waits until the
// sphere count is reached and SECONDS more (default 5), turns the view by dragging the mouse
// DX,DY pixels from the middle (400,0: half a turn), clicks at the --click position (selects a
// sphere), moves the mouse to X,Y (a hovered sphere is drawn stronger, with a thin outline; its
// cluster's points lighter), presses KEYS one by one (e.g. 'e': the error map; 'p': hide the points), takes a
// 1280x800 screenshot and stops vmas.
import { spawn } from 'node:child_process';
import path from 'node:path';
import readline from 'node:readline';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const args = process.argv.slice(2);
const dashes = args.indexOf('--');
const vmasOptions = dashes >= 0 ? args.splice(dashes).slice(1) : [];
const option = (name) => { const i = args.indexOf(name); return i >= 0 ? args.splice(i, 2)[1] : undefined; };
const orbit = option('--orbit'), hover = option('--hover'), click = option('--click'), keys = option('--keys') ?? '';
const settle = Number(option('--settle') ?? 5);
if (args.length !== 2) {
  console.error('usage: node tests/browser/screenshot.mjs INPUT OUT.png [--orbit DX,DY] [--click X,Y] [--hover X,Y] ' +
                '[--keys KEYS] [--settle SECONDS] [-- VMAS_EDIT_OPTIONS...]');
  process.exit(2);
}
const [input, output] = args;
const vmasBinary = path.resolve(process.env.VMAS_BINARY || path.join(repo, 'build/vmas'));

const vmas = spawn(vmasBinary, ['edit', input, ...vmasOptions], { stdio: ['ignore', 'pipe', 'inherit'] });
const exited = new Promise((resolve) => vmas.on('exit', resolve));
let browser = null;
try {
  const url = await new Promise((resolve, reject) => {
    readline.createInterface({ input: vmas.stdout }).once('line', resolve);
    vmas.on('exit', () => reject(new Error('vmas exited before printing its URL')));
  });
  browser = await chromium.launch({
    executablePath: process.env.VMAS_CHROMIUM || '/usr/bin/chromium',
    args: ['--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader',
           '--disable-background-networking', '--disable-component-update', '--disable-sync',
           '--disable-quic', '--no-first-run'] });
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  page.on('pageerror', (error) => console.error(`page error: ${error.message}`));
  await page.goto(url);
  await page.waitForFunction(() => /^spheres (\d+)\/\1 /.test(document.getElementById('status').textContent),
                             null, { timeout: 120_000 });
  await page.waitForTimeout(settle * 1000);
  if (orbit) {
    const [dx, dy] = orbit.split(',').map(Number);
    await page.mouse.move(640, 400);
    await page.mouse.down();
    for (let i = 1; i <= 20; ++i) await page.mouse.move(640 + dx * i / 20, 400 + dy * i / 20);
    await page.mouse.up();
    await page.waitForTimeout(500);
  }
  if (click) {
    const [x, y] = click.split(',').map(Number);
    await page.mouse.click(x, y);
  }
  if (hover) {
    const [x, y] = hover.split(',').map(Number);
    await page.mouse.move(x, y);
  }
  for (const key of keys) await page.keyboard.press(key);
  await page.waitForTimeout(keys.includes('e') ? 3000 : 500);  // the error map is fetched
  await page.screenshot({ path: output });
  console.log(`${output}: ${await page.textContent('#status')}`);
} finally {
  if (browser) await browser.close();
  vmas.kill('SIGINT');
  await exited;
}
