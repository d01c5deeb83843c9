// Soak test of `vmas edit` and its page (issue 49, item 6; not in CI: it takes minutes): the
// bunny scan of clouds/, one edit a second through the keys as a person makes them (remove the
// sphere under the pointer, split there, freeze, +, −, undo, redo, a finish now and then), and
// the memory of the server (vmas-edit's resident set) and of the page (its JavaScript heap)
// sampled every 30 s. After the first minute (warm-up) neither may grow by more than 20 %.
//
// usage: node tests/browser/soak.mjs [VMAS_BINARY] [MINUTES]     (or scripts/soak-editor)
// Prints a line per sample and a verdict; exits 1 when memory grew too much or anything failed.
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import path from 'node:path';
import readline from 'node:readline';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';

const repo = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '../..');
const vmasBinary = path.resolve(process.argv[2] || path.join(repo, 'build/vmas'));
const minutes = Number(process.argv[3] || 10);
const input = path.join(repo, 'clouds/bunny_merged_45k.xyz');
const SAMPLE_MS = 30_000, WARM_UP_MS = 60_000, MAX_GROWTH = 0.20;

const vmas = spawn(vmasBinary, ['edit', input, '--spheres', '60', '--threads', '2'],
                   { stdio: ['ignore', 'pipe', 'inherit'] });
const url = await new Promise((resolve, reject) => {
  readline.createInterface({ input: vmas.stdout }).once('line', resolve);
  vmas.once('exit', (code) => reject(new Error(`vmas edit exited (${code}) before printing its URL`)));
});
const browser = await chromium.launch({
  executablePath: process.env.VMAS_CHROMIUM || '/usr/bin/chromium',
  args: ['--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader',
         '--enable-precise-memory-info', '--disable-background-networking', '--no-first-run'] });
const page = await (await browser.newContext({ viewport: { width: 1280, height: 800 } })).newPage();
const errors = [];
page.on('pageerror', (error) => errors.push(`uncaught: ${error.message}`));
page.on('console', (m) => { if (m.type() === 'error') errors.push(`console error: ${m.text()}`); });
await page.goto(url);
await page.waitForFunction(() => /^spheres 60\/60 /.test(document.getElementById('status').textContent),
                           null, { timeout: 120_000 });

// vmas edit runs vmas-edit in its own process (exec: the same pid).
const serverKb = () => Number(/VmRSS:\s+(\d+)/.exec(fs.readFileSync(`/proc/${vmas.pid}/status`, 'utf8'))[1]);
const pageKb = () => page.evaluate(() => Math.round(performance.memory.usedJSHeapSize / 1024));
const canvas = await page.locator('#view canvas').boundingBox();
const keys = ['d', 's', 'f', '+', '-', 'Control+z', 'Control+Shift+z', 'd', 's', '+'];
let seed = 7;  // the same edits every run
const random = () => ((seed = (Math.imul(seed, 1664525) + 1013904223) >>> 0) / 2 ** 32);

const start = Date.now();
const samples = [];
let edits = 0, lastSample = 0;
while (Date.now() - start < minutes * 60_000) {
  // The pointer somewhere over the middle of the view, where the bunny is.
  await page.mouse.move(canvas.x + canvas.width * (0.35 + 0.3 * random()),
                        canvas.y + canvas.height * (0.3 + 0.4 * random()));
  const key = edits % 120 === 119 ? 'Enter' : keys[Math.floor(random() * keys.length)];
  if (key === 'Enter') await page.locator('#finish').click().catch(() => {});
  else await page.keyboard.press(key);
  ++edits;
  if (key === 'Enter') await page.waitForTimeout(5000);  // a finish, then the run goes on
  if (await page.locator('#status').textContent().then((s) => / paused /.test(s)))
    await page.keyboard.press(' ');
  await page.waitForTimeout(1000);
  const elapsed = Date.now() - start;
  if (elapsed - lastSample >= SAMPLE_MS) {
    lastSample = elapsed;
    const sample = { seconds: Math.round(elapsed / 1000), server: serverKb(), page: await pageKb() };
    samples.push(sample);
    console.log(`${sample.seconds} s: ${edits} edits, server ${(sample.server / 1024).toFixed(1)} MB, ` +
                `page heap ${(sample.page / 1024).toFixed(1)} MB`);
  }
}
samples.push({ seconds: Math.round((Date.now() - start) / 1000), server: serverKb(), page: await pageKb() });
vmas.kill('SIGINT');
await browser.close();

const warm = samples.find((s) => s.seconds * 1000 >= WARM_UP_MS) || samples[0];
const last = samples[samples.length - 1];
const growth = (what) => last[what] / warm[what] - 1;
console.log(`after ${minutes} min and ${edits} edits, from ${warm.seconds} s to ${last.seconds} s: ` +
            `server ${(100 * growth('server')).toFixed(1)} %, page heap ${(100 * growth('page')).toFixed(1)} %`);
const failures = [...errors];
for (const what of ['server', 'page'])
  if (growth(what) > MAX_GROWTH) failures.push(`${what} memory grew by more than ${100 * MAX_GROWTH} %`);
for (const f of failures) console.log(`FAIL: ${f}`);
console.log(failures.length ? 'soak: FAILED' : 'soak: passed');
process.exit(failures.length ? 1 : 0);
