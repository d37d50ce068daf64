// `sscs serve` in a real browser (chromium-headless-shell through puppeteer-core): a copy of the
// reference store served; the page's camera and its table's search are changed; a save that
// narrows the aisle reloads the page with the new failure, the same camera and the same search;
// a typo shows its file:line:col over the last good view; the fix recovers; no console error
// (the page's content security policy lets its live script run and connect back).
// Usage: SSCS=path/to/sscs SSCS_SOURCE=source dir node --test serve.test.mjs
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { mkdtempSync, copyFileSync, readFileSync, writeFileSync, rmSync, existsSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import puppeteer from 'puppeteer-core';

const sscs = process.env.SSCS, source = process.env.SSCS_SOURCE;
assert.ok(sscs && source, 'SSCS and SSCS_SOURCE are set');
const chromium = ['/usr/bin/chromium-headless-shell', '/usr/bin/chromium'].find(existsSync);
const dir = mkdtempSync(join(tmpdir(), 'sscs-serve-'));
const vault = join(dir, 'store.yaml');
copyFileSync(join(source, 'scenarios/drum-store/store.yaml'), vault);
const text = readFileSync(vault, 'utf8');
let server, browser, base;

before(async () => {
  server = spawn(sscs, ['serve', 'store.yaml', '--port', '0'], { cwd: dir, stdio: ['ignore', 'pipe', 'inherit'] });
  base = await new Promise((resolve, reject) => {
    let seen = '';
    server.stdout.on('data', (d) => {
      seen += d;
      const m = seen.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
      if (m) resolve(m[0]);
    });
    server.on('exit', (code) => reject(new Error(`sscs serve exited (${code}): ${seen}`)));
  });
  browser = await puppeteer.launch({
    executablePath: chromium, headless: 'shell',
    args: ['--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader', '--disable-background-networking',
           '--disable-component-update', '--no-first-run', '--disable-sync', '--disable-quic'],
  });
});
after(async () => {
  await browser?.close();
  server?.kill('SIGINT');
  rmSync(dir, { recursive: true, force: true });
});

const failed = (page) => page.evaluate(() => window.sscsReport.data.reports[0].failed);
const camera = (page) => page.evaluate(() => {
  const v = window.sscsReport.view;
  return [...v.orbitCamera.position.toArray(), ...v.controls.target.toArray()];
});

/** The served page, loaded and its report ready; its page errors collected in `problems`. */
async function openServed() {
  const page = await browser.newPage();
  await page.setViewport({ width: 1400, height: 900 });
  const problems = [];
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  await page.goto(base);
  await page.waitForFunction('window.sscsReport !== undefined', { timeout: 30000 });
  await page.evaluate('window.sscsReport.ready');
  return { page, problems };
}

/** Saves `content` and waits until the page shows the check of it, its report ready: the time
 *  taken. The page takes it in place: a mark left on the page before survives (no reload). */
async function save(page, content) {
  const shown = await page.evaluate(() => { window.sscsTestMark = 'kept'; return window.sscsServeShown; });
  const t0 = Date.now();
  writeFileSync(vault, content);
  await page.waitForFunction((g) => window.sscsServeShown > g, { timeout: 30000 }, shown);
  await page.evaluate('window.sscsReport.ready');
  const took = Date.now() - t0;
  assert.equal(await page.evaluate(() => window.sscsTestMark), 'kept', 'the page took the update in place (it reloaded)');
  return took;
}

test('a save updates the page in place with its verdicts, its camera and its search kept; a typo shows where it is', async () => {
  const page = await browser.newPage();
  await page.setViewport({ width: 1400, height: 900 });
  const problems = [];
  page.on('console', (m) => { if (m.type() === 'error') problems.push(`console: ${m.text()}`); });
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  await page.goto(base);
  await page.waitForFunction('window.sscsReport !== undefined', { timeout: 30000 });
  await page.evaluate('window.sscsReport.ready');
  assert.equal(await failed(page), 0);
  // A camera of the user's own, and a search in the table.
  await page.evaluate(() => {
    const v = window.sscsReport.view;
    v.orbitCamera.position.set(3, -7, 9);
    v.controls.target.set(6, 4, 1);
    v.controls.update();
  });
  await page.type('input[data-filter=text]', 'aisle');
  const before = await camera(page);

  const took = await save(page, text.replace('aisle: {value: 3.2 m', 'aisle: {value: 2.2 m'));
  console.log(`serve: a save of the store to the page updated in place and ready in a browser: ${took} ms ` +
              `(in the page, ms: ${JSON.stringify(await page.evaluate(() => window.sscsServeTimes))})`);
  assert.equal(await failed(page), 1);
  const after = await camera(page);
  after.forEach((x, k) => assert.ok(Math.abs(x - before[k]) < 1e-6, `camera kept: ${after} vs ${before}`));
  assert.equal(await page.$eval('input[data-filter=text]', (e) => e.value), 'aisle');
  const rows = await page.$$eval('[data-testid=results] tbody tr', (r) => r.map((x) => x.textContent));
  assert.ok(rows.length >= 1 && rows.every((r) => /aisle/i.test(r)), `the search kept: ${rows.length} rows`);

  await save(page, text.replace('aisle: {value: 3.2 m', 'aisle: {valu: 3.2 m'));
  const banner = await page.$eval('[data-testid=serve-errors]', (e) => e.textContent);
  assert.match(banner, /store\.yaml:9:11: error: unknown key 'valu'/);
  assert.match(banner, /did you mean 'value'/);
  assert.equal(await failed(page), 1, 'the last good view stays');

  await save(page, text);
  assert.equal(await page.$('[data-testid=serve-errors]'), null);
  assert.equal(await failed(page), 0);

  // A save that moves the racks and changes no verdict: the model is new all the same (review 19:
  // the page kept the old layout when its report's data had not changed).
  const rowX = () => page.evaluate(() => {
    const node = window.sscsReport.view.objects.get('Row_1');
    const box = new THREE.Box3().setFromObject(node);
    return box.min.x;
  });
  const x0 = await rowX();
  await save(page, text.replace('first_row_x: 10 m', 'first_row_x: 10.5 m'));
  assert.equal(await failed(page), 0);
  assert.ok(Math.abs((await rowX()) - x0 - 0.5) < 1e-6, `Row_1 moved 0.5 m in the view: ${x0} -> ${await rowX()}`);
  assert.deepEqual(problems, []);
  await page.close();
});

test('a failed reach row selected keeps its picture through a save: the device at its closest pose, the rod to the new target', async () => {
  const { page, problems } = await openServed();
  // The crane asked to hold its hook 9 m above every rack position: out of its reach.
  const above = (z) => text.replace('offset: {xyz: [0, 0, 1.2]}', `offset: {xyz: [0, 0, ${z}]}`);
  await save(page, above(9));
  const id = await page.evaluate(() => window.sscsReport.rows.find((r) => r.closest).id);
  await page.click(`[data-testid=results] tbody tr[data-id="${id}"]`);
  await page.evaluate('window.sscsReport.view.ready');
  const picture = () => page.evaluate(() => {
    const v = window.sscsReport.view;
    return v.closest && { device: v.closest.device, ball: v.closest.group.children.at(-1).position.toArray(), dots: v.reach ? v.reach.children.map((c) => c.name) : [] };
  });
  const first = await picture();
  assert.ok(first && first.device === 'Crane', JSON.stringify(first));
  assert.deepEqual(first.dots, ['Crane']);
  await save(page, above(10));
  const second = await picture();
  assert.ok(second, 'the picture is drawn again after the save');
  assert.ok(Math.abs(second.ball[2] - first.ball[2] - 1) < 1e-6 && Math.abs(second.ball[0] - first.ball[0]) < 1e-6,
            `the target 1 m higher: ${first.ball} -> ${second.ball}`);
  assert.deepEqual(second.dots, ['Crane']);
  await save(page, text);
  assert.equal(await failed(page), 0);
  assert.equal(await page.evaluate('window.sscsReport.view.closest'), null, 'nothing fails: no picture');
  assert.deepEqual(problems, []);
  await page.close();
});

test('a save sends the page what changed alone: the objects drawn differently, and those gone', async () => {
  const { page, problems } = await openServed();
  // What the server sends a page that shows generation g: the names of the objects in its model, and those gone.
  const sent = (g) => page.evaluate(async (g) => {
    const u = await (await fetch(`/update?from=${g}`)).json();
    if (u.full) return { full: true };
    let objects = [];
    if (u.model) {
      const bytes = Uint8Array.from(atob(u.model), (c) => c.charCodeAt(0));
      const length = new DataView(bytes.buffer).getUint32(12, true);  // the GLB's JSON chunk
      const gltf = JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + length)));
      objects = gltf.nodes.filter((n) => n.extras && n.extras.sscs && n.extras.sscs.object && !n.extras.sscs.part).map((n) => n.name);
    }
    return { objects: objects.sort(), removed: u.removed };
  }, g);
  const goodsX = () => page.evaluate(() => new THREE.Box3().setFromObject(window.sscsReport.view.objects.get('GoodsRack')).min.x);
  const x0 = await goodsX();
  const g0 = await page.evaluate(() => window.sscsServeShown);
  const moved = text.replace('name: GoodsRack, parent: Hall, location: [9, 2.0, 0]', 'name: GoodsRack, parent: Hall, location: [9.5, 2.0, 0]');
  assert.notEqual(moved, text);
  await save(page, moved);
  assert.deepEqual(await sent(g0), { objects: ['GoodsRack'], removed: [] });
  assert.ok(Math.abs((await goodsX()) - x0 - 0.5) < 1e-6, 'the page moved it 0.5 m');
  // An object taken out of the vault: taken out of the view; a page far behind gets the whole page.
  const g1 = await page.evaluate(() => window.sscsServeShown);
  await save(page, moved.replace(/^  - \{type: pallet, name: Dock,.*\n/m, ''));
  assert.deepEqual(await sent(g1), { objects: [], removed: ['Dock'] });
  assert.equal(await page.evaluate(() => window.sscsReport.view.objects.has('Dock')), false);
  assert.deepEqual(await sent(-5), { full: true });
  // Back as it was: what changed since Dock went (Dock again, GoodsRack back), and since g1 (GoodsRack).
  const g2 = await page.evaluate(() => window.sscsServeShown);
  await save(page, text);
  assert.deepEqual(await sent(g2), { objects: ['Dock', 'GoodsRack'], removed: [] });
  assert.deepEqual(await sent(g1), { objects: ['GoodsRack'], removed: [] });
  assert.equal(await page.evaluate(() => window.sscsReport.view.objects.has('Dock')), true);
  assert.ok(Math.abs((await goodsX()) - x0) < 1e-6);
  // The view patched save by save is the view of the page loaded afresh: the same objects, where they are.
  const drawn = (p) => p.evaluate(() => {
    const v = window.sscsReport.view, out = {};
    v.model.updateMatrixWorld(true);
    for (const [name, node] of v.objects) {
      const b = new THREE.Box3().setFromObject(node);
      out[name] = [...b.min.toArray(), ...b.max.toArray()].map((x) => x.toFixed(6)).join(' ');
    }
    return out;
  });
  const fresh = await browser.newPage();
  await fresh.goto(base);
  await fresh.waitForFunction('window.sscsReport !== undefined', { timeout: 30000 });
  await fresh.evaluate('window.sscsReport.ready');
  assert.deepEqual(await drawn(page), await drawn(fresh));
  await fresh.close();
  assert.deepEqual(problems, []);
  await page.close();
});
