#!/usr/bin/env node
// The live design loop in a browser (issue 38): `sscs serve` of a vault, a save, and the open page
// updated in place and its view drawn (headless chromium, software WebGL), best and median of N
// saves, for each sscs binary given (a baseline first, then this one), side by side.
//
//   node tools/bench/live_page.mjs [--runs 5] [--objects 10000] SSCS [SSCS ...]
//
// Vaults: the reference store (scenarios/drum-store/store.yaml, its aisle edited) and a generated
// one (tools/bench/gen_vault.py: N objects, N constraints; one rack's height edited). Targets:
// 300 ms and 2 s. Needs tests/web/node_modules (tools/test.sh installs it).
import { spawn, execFileSync } from 'node:child_process';
import { mkdtempSync, copyFileSync, readFileSync, writeFileSync, rmSync } from 'node:fs';
import { join, dirname, resolve } from 'node:path';
import { tmpdir } from 'node:os';
import { fileURLToPath } from 'node:url';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '..', '..');
const { default: puppeteer } = await import(join(root, 'tests/web/node_modules/puppeteer-core/lib/esm/puppeteer/puppeteer-core.js'));
const args = process.argv.slice(2);
const option = (name, value) => { const i = args.indexOf(name); if (i < 0) return value; const v = +args[i + 1]; args.splice(i, 2); return v; };
const runs = option('--runs', 5), objects = option('--objects', 10000);
if (!args.length) { console.error('usage: live_page.mjs [--runs N] [--objects N] SSCS [SSCS ...]'); process.exit(2); }

const dir = mkdtempSync(join(tmpdir(), 'sscs-live-page-'));
copyFileSync(join(root, 'scenarios/drum-store/store.yaml'), join(dir, 'store.yaml'));
execFileSync('python3', [join(root, 'tools/bench/gen_vault.py'), join(dir, 'big.yaml'), '--objects', String(objects), '--constraints', String(objects)]);
const vaults = [
  { name: 'reference store', file: 'store.yaml', target: 300, edit: (t, i) => t.replace('aisle: {value: 3.2 m', `aisle: {value: ${3.2 + 0.1 * ((i % 3) + 1)} m`) },
  { name: `${objects} objects`, file: 'big.yaml', target: 2000, edit: (t, i) => t.replace(/height: 3\.\d+, levels/, `height: ${3.1 + 0.1 * (i % 5)}, levels`) },
];
const browser = await puppeteer.launch({ executablePath: '/usr/bin/chromium-headless-shell', headless: 'shell',
  args: ['--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader'] });

async function measure(sscs, vault) {
  const path = join(dir, vault.file), text = readFileSync(path, 'utf8');
  const server = spawn(sscs, ['serve', vault.file, '--port', '0'], { cwd: dir, stdio: ['ignore', 'pipe', 'inherit'] });
  const base = await new Promise((res) => { let s = ''; server.stdout.on('data', (d) => { s += d; const m = s.match(/http:\/\/127\.0\.0\.1:(\d+)\//); if (m) res(m[0]); }); });
  const page = await browser.newPage();
  await page.setViewport({ width: 1400, height: 900 });
  await page.goto(base, { timeout: 300000 });
  await page.waitForFunction('window.sscsReport !== undefined', { timeout: 300000 });
  await page.evaluate('window.sscsReport.ready');
  const times = [];
  for (let i = 0; i < runs; i++) {
    const shown = await page.evaluate(() => window.sscsServeShown);
    const t0 = Date.now();
    writeFileSync(path, vault.edit(text, i));
    await page.waitForFunction((g) => window.sscsServeShown > g, { timeout: 300000, polling: 10 }, shown);
    await page.evaluate('window.sscsReport.ready');
    times.push(Date.now() - t0);
  }
  writeFileSync(path, text);
  await page.close();
  server.kill('SIGINT');
  await new Promise((res) => server.on('exit', res));
  times.sort((a, b) => a - b);
  return { best: times[0], median: times[Math.floor(times.length / 2)] };
}

console.log(`save -> page updated in place and drawn (chromium, software WebGL), best/median of ${runs}, ms`);
for (const vault of vaults) {
  const cells = [];
  for (const sscs of args) cells.push(await measure(resolve(sscs), vault));  // (run in a folder of its own)
  const ratio = cells.length > 1 ? `  ${(cells[0].median / cells[cells.length - 1].median).toFixed(2)}x faster` : '';
  console.log(`${vault.name.padEnd(18)} ${cells.map((c, k) => `${args[k]}: ${c.best}/${c.median}`).join('   ')}   target ${vault.target}${ratio}`);
}
await browser.close();
rmSync(dir, { recursive: true, force: true });
