// The HTML reports in a real browser: Debian's chromium-headless-shell driven by puppeteer-core.
// Every report tests/web/make-reports.sh made from scenarios/ (in SSCS_WEB_OUT) must load from
// disk with no console error and no network request, show a 3D view that is not blank, list the
// rows of its JSON; clicking a failing row highlights its object, clicking an object lists its
// constraints, scrubbing to an event moves the scene, clicking a sweep point selects its row.
// Screenshots go to SSCS_WEB_OUT/screenshots (docs/reports.md shows them: SSCS_UPDATE_DOCS=1).
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { readdirSync, readFileSync, existsSync, mkdirSync, copyFileSync } from 'node:fs';
import { join, basename, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

const out = process.env.SSCS_WEB_OUT;
assert.ok(out && existsSync(out), 'SSCS_WEB_OUT names the folder make-reports.sh filled');
const shots = join(out, 'screenshots');
mkdirSync(shots, { recursive: true });
const chromium = ['/usr/bin/chromium-headless-shell', '/usr/bin/chromium'].find(existsSync);
const pages = readdirSync(out).filter((f) => f.endsWith('.html')).sort();
let browser;

before(async () => {
  assert.ok(chromium, 'chromium-headless-shell is installed (tools/setup.sh)');
  browser = await puppeteer.launch({
    executablePath: chromium, headless: 'shell',
    args: ['--no-sandbox', '--enable-unsafe-swiftshader', '--use-angle=swiftshader', '--disable-background-networking',
           '--disable-component-update', '--no-first-run', '--disable-sync', '--disable-quic'],
  });
});
after(async () => { await browser?.close(); });

/** Opens a report: every console error, page error and request that leaves the file is kept. */
async function open(file, size) {
  const page = await browser.newPage();
  // The docs' screenshots (and a layout asserted at that size) at 1400x900; the other tests at
  // 1000x640, half the pixels SwiftShader draws (each page is drawn on the CPU).
  await page.setViewport(process.env.SSCS_UPDATE_DOCS || size === 'docs' ? { width: 1400, height: 900 } : { width: 1000, height: 640 });
  const problems = [];
  page.on('console', (m) => { if (m.type() === 'error') problems.push(`console: ${m.text()}`); });
  page.on('pageerror', (e) => problems.push(`page error: ${e.message}`));
  await page.setRequestInterception(true);
  page.on('request', (r) => {
    const url = r.url();
    if (url.startsWith('data:') || url.startsWith('blob:') || url === `file://${join(out, file)}`) return r.continue();
    problems.push(`network: ${url}`);
    r.abort();
  });
  await page.goto(`file://${join(out, file)}`);
  await page.waitForFunction('window.sscsReport !== undefined', { timeout: 30000 });
  await page.evaluate('window.sscsReport.ready');
  await page.evaluate(CANVAS_HELPERS);
  return { page, problems };
}

// In the page: the 3D canvas's pixels (its drawing buffer is preserved), how many differ from the
// background, and how many differ from an earlier snapshot.
const CANVAS_HELPERS = `
window.__pixels = () => {
  const c = document.querySelector('canvas[data-testid=view3d]');
  const t = document.createElement('canvas'); t.width = c.width; t.height = c.height;
  const g = t.getContext('2d'); g.drawImage(c, 0, 0);
  return g.getImageData(0, 0, t.width, t.height).data;
};
window.__notBackground = () => {
  const d = window.__pixels(); let n = 0;
  for (let i = 0; i < d.length; i += 4) if (Math.abs(d[i] - 244) + Math.abs(d[i + 1] - 245) + Math.abs(d[i + 2] - 247) > 30) n++;
  return n / (d.length / 4);
};
window.__snap = () => { window.__before = window.__pixels(); };
window.__changed = () => {
  const a = window.__before, b = window.__pixels(); let n = 0;
  for (let i = 0; i < a.length; i += 4) if (Math.abs(a[i] - b[i]) + Math.abs(a[i + 1] - b[i + 1]) + Math.abs(a[i + 2] - b[i + 2]) > 30) n++;
  return n;
};`;

const shot = (page, name) => page.screenshot({ path: join(shots, `${name}.png`) });
const kind = (page) => page.evaluate('window.sscsReport.kind');

for (const file of pages) {
  const name = basename(file, '.html');
  test(`${file}: loads from disk, no console error, no network, a 3D view that is not blank`, async () => {
    const { page, problems } = await open(file);
    assert.deepEqual(problems, []);
    if (await kind(page) !== 'sweep') {
      const drawn = await page.evaluate('window.__notBackground()');
      assert.ok(drawn > 0.03, `the 3D view draws on ${(drawn * 100).toFixed(1)}% of its pixels`);
    }
    await shot(page, name);
    await page.close();
  });
}

/** A name as the page draws it: bidirectional controls shown as marks (logic.js showControls). */
const shownText = (text) => text.replace(/[\u061c\u200e\u200f\u202a-\u202e\u2066-\u2069]/g,
  (c) => `\u27e8U+${c.charCodeAt(0).toString(16).toUpperCase().padStart(4, '0')}\u27e9`);

/** The check reports and the JSON each was made with (demo-from-json.html: from demo.json). */
const fromJson = { 'demo-from-json.html': 'demo.json', 'variant-from-json.html': 'aisle-rows/54-aisle=2m-rows=5/report.json' };
const checks = pages.filter((f) => existsSync(join(out, f.replace('.html', '.json'))) || f in fromJson);
const jsonOf = (f) => JSON.parse(readFileSync(join(out, fromJson[f] || f.replace('.html', '.json')), 'utf8'));

for (const file of checks) {
  test(`${file}: the table's rows are the JSON report's`, async () => {
    const { page } = await open(file);
    const report = jsonOf(file);
    const reports = report.reports || [report];
    const expected = reports.flatMap((r) => r.results.map((x) => x.constraint).concat(((r.baseline || {}).removed || []).map((x) => x.constraint)))
      .map(shownText);
    const shown = await page.$$eval('table.results tbody tr .name', (cells) => cells.map((c) => c.textContent));
    assert.deepEqual(shown, expected);
    // Filtering by status keeps exactly the failing rows (a report without one offers no such filter).
    // (a failed warning is filtered as a warning, as the text report counts it)
    const fails = reports.flatMap((r) => r.results.filter((x) => x.status === 'fail' && x.severity !== 'warning').map((x) => shownText(x.constraint)));
    const offered = await page.$$eval('select[data-filter=status] option', (os) => os.map((o) => o.value));
    assert.equal(offered.includes('fail'), fails.length > 0, offered.join(','));
    if (fails.length) {
      await page.select('select[data-filter=status]', 'fail');
      const failing = await page.$$eval('table.results tbody tr .name', (cells) => cells.map((c) => c.textContent));
      assert.deepEqual(failing, fails);
    }
    await page.close();
  });
}

test('demo.html: clicking a failing row highlights and frames its object; clicking an object lists its constraints', async () => {
  const { page } = await open('demo.html');
  const row = await page.$('table.results tbody tr.fail');
  const subjects = await row.evaluate((tr) => tr.dataset.subjects.split('|').filter(Boolean));
  assert.ok(subjects.length > 0);
  await page.evaluate('window.__snap()');
  await row.click();
  assert.equal(await row.evaluate((tr) => tr.classList.contains('selected')), true);
  const emissive = await page.evaluate((n) => {
    let hex = null;
    window.sscsReport.view.objects.get(n).traverse((m) => { if (m.isMesh && hex === null) hex = m.material.emissive.getHex(); });
    return hex;
  }, subjects[0]);
  assert.equal(emissive, 0x1f77b4, `${subjects[0]} is drawn highlighted`);
  assert.ok(await page.evaluate('window.__changed()') > 500, 'the view moved to the object and coloured it');
  await shot(page, 'demo-row-selected');
  // The object in the middle of the view, clicked: its constraints are listed, the table filtered.
  const at = await page.evaluate((n) => window.sscsReport.view.screenPoint(n), subjects[0]);
  await page.mouse.click(at.x, at.y);
  const listed = await page.$eval('[data-testid=object-panel] h3', (h) => h.textContent);
  assert.equal(listed, subjects[0]);
  const objects = await page.$$eval('table.results tbody tr', (rows) => rows.map((tr) => tr.dataset.subjects));
  assert.ok(objects.length > 0 && objects.every((o) => o.split('|').includes(listed)), objects.join(' ; '));
  await page.close();
});

test('devices.html: a failed reach row draws its device at the closest pose, a rod from its tool to the target; another row puts it back', async () => {
  const { page, problems } = await open('devices.html');
  const data = await page.evaluate(() => window.sscsReport.rows.filter((r) => r.closest).map((r) => ({ id: r.id, device: r.subjects[0], closest: r.closest, message: r.message })));
  assert.ok(data.length >= 3, `rows with a closest pose: ${data.length}`);
  // The tool's distance from the device as drawn (its box in sscs's z-up world, the model root's frame).
  const toolGap = (device, tool) => page.evaluate((device, tool) => {
    const v = window.sscsReport.view, root = v.model.children[0];
    root.updateMatrixWorld(true);
    const box = new THREE.Box3().setFromObject(v.objects.get(device)).applyMatrix4(new THREE.Matrix4().getInverse(root.matrixWorld));
    return box.distanceToPoint(new THREE.Vector3(...tool));
  }, device, tool);
  for (const row of data) {
    const rest = await page.evaluate((d) => window.sscsReport.view.objects.get(d).children.map((n) => n.position.toArray().join()).join(';'), row.device);
    await page.click(`table.results tbody tr[data-id="${row.id}"]`);
    await page.evaluate('window.sscsReport.view.ready');
    const shown = await page.evaluate(() => {
      const c = window.sscsReport.view.closest;
      return c && { device: c.device, parts: c.saved.length, things: c.group.children.length };
    });
    assert.ok(shown && shown.device === row.device && shown.parts > 0, `${row.message}: ${JSON.stringify(shown)}`);
    const gap = Math.hypot(...row.closest.tool.map((x, k) => x - row.closest.target[k]));
    assert.equal(shown.things, gap > 1e-6 ? 2 : 1, 'a rod when the tool stops short, and the ball on the target');
    // The device drawn at its closest pose holds its tool (within a part's thickness): the parts' poses are applied in its frame.
    assert.ok(await toolGap(row.device, row.closest.tool) < 0.05, `${row.device}'s tool ${row.closest.tool} lies off the posed device`);
    // Where that device reaches, as dots (and no other device's).
    assert.deepEqual(await page.evaluate(() => window.sscsReport.view.reach.children.map((c) => c.name)), [row.device]);
    await shot(page, `devices-closest-${row.device}`);
    // A passing row: the device as it stands again.
    await page.click('table.results tbody tr.pass');
    await page.evaluate('window.sscsReport.view.ready');
    assert.equal(await page.evaluate('window.sscsReport.view.closest'), null);
    const back = await page.evaluate((d) => window.sscsReport.view.objects.get(d).children.map((n) => n.position.toArray().join()).join(';'), row.device);
    assert.equal(back, rest, `${row.device} back at its pose`);
  }
  // The switch: every device's dots, whatever row is selected; off: none.
  const devices = await page.evaluate(() => Object.keys(window.sscsReport.data.reach[0]).sort());
  assert.ok(devices.length >= 5, devices.join());
  await page.click('[data-testid=reach]');
  await page.evaluate('window.sscsReport.view.ready');
  assert.deepEqual(await page.evaluate(() => window.sscsReport.view.reach.children.map((c) => c.name).sort()), devices);
  assert.ok(await page.evaluate(() => window.sscsReport.view.reach.children.every((c) => c.geometry.attributes.position.count === 800)));
  await shot(page, 'devices-reach');
  await page.click('[data-testid=reach]');
  await page.evaluate('window.sscsReport.view.ready');
  assert.equal(await page.evaluate('window.sscsReport.view.reach'), null);
  assert.deepEqual(problems, []);
  await page.close();
});

test('two-vaults.html: a row of the second vault shows that vault in 3D', async () => {
  const { page } = await open('two-vaults.html');
  const report = jsonOf('two-vaults.html');
  const second = report.reports[1];
  const row = await page.$(`table.results tbody tr[data-id^="1:"]`);
  await row.click();
  await page.waitForFunction('window.sscsReport.view && window.sscsReport.view.objects.size > 0');
  await page.evaluate('window.sscsReport.view.ready');
  const shown = await page.evaluate('[...window.sscsReport.view.objects.keys()]');
  for (const r of second.results) for (const s of r.subject) assert.ok(shown.includes(s), `${s} of ${second.vault} is in the view`);
  assert.equal(await page.$eval('select[data-testid=vault]', (s) => s.value), '1');
  assert.equal((await page.$$('canvas[data-testid=view3d]')).length, 1, 'one view at a time');
  await page.close();
});

test('variant-from-json.html: a sweep variant report is drawn with the values of the variant', async () => {
  const { page } = await open('variant-from-json.html');
  const report = jsonOf('variant-from-json.html');
  assert.equal(report.set.rows, '5');
  const shown = await page.evaluate('[...window.sscsReport.view.objects.keys()]');
  for (const r of report.results) for (const s of r.subject) assert.ok(shown.includes(s), `${s} is in the view`);
  assert.ok(shown.includes('Rack_5_1'), 'five rows of racks, as the variant had');
  await page.close();
});

test('ci-branch.html: the baseline diff is in the table (new, fixed, still failing) and the summary', async () => {
  const { page } = await open('ci-branch.html');
  const report = jsonOf('ci-branch.html');
  const changes = await page.$$eval('table.results tbody tr td:nth-child(2)', (cells) => cells.map((c) => c.textContent));
  const renamed = new Map(report.baseline.renamed.map((x) => [x.to, x.from]));
  const expected = report.results.map((r) => (renamed.has(r.constraint) ? `renamed (was ${renamed.get(r.constraint)})` : r.baseline.replace(/_/g, ' ')))
    .concat(report.baseline.removed.map(() => 'removed'));
  assert.ok(renamed.size > 0, 'the CI example renames a constraint');
  assert.deepEqual(changes, expected);
  const summary = await page.$eval('[data-testid=baseline]', (e) => e.textContent);
  assert.match(summary, new RegExp(`${report.baseline.new} new, ${report.baseline.fixed} fixed`));
  await page.select('select[data-filter=change]', 'new');
  assert.equal((await page.$$('table.results tbody tr')).length, report.baseline.new);
  await page.close();
});

for (const file of pages.filter((f) => existsSync(join(out, basename(f, '.html'), 'summary.json')))) {
  test(`${file}: scrubbing to an event moves the scene; the timeline, plots and breakdown are there`, async () => {
    const { page } = await open(file);
    const summary = JSON.parse(readFileSync(join(out, basename(file, '.html'), 'summary.json'), 'utf8'));
    assert.equal((await page.$$('table.breakdown tr')).length, summary.steps.length);
    const events = await page.evaluate('window.sscsReport.events');
    // The event the most into the run (a device has moved by then).
    const i = events.reduce((best, e, k) => (e.t > events[best].t ? k : best), 0);
    await page.evaluate('window.sscsReport.seek(0)');
    await page.evaluate('window.__snap()');
    await page.click(`table.events tr[data-event="${i}"]`);
    const t = await page.evaluate('window.sscsReport.view.time');
    assert.ok(Math.abs(t - Math.min(events[i].t, await page.evaluate('window.sscsReport.view.duration'))) < 1e-6, `at ${t}, event at ${events[i].t}`);
    assert.equal(await page.$eval('[data-testid=time]', (e) => e.textContent), `${t.toFixed(2)} s`);
    assert.ok(await page.evaluate('window.__changed()') > 200, 'the device is drawn elsewhere');
    assert.ok((await page.$$('svg.plot polyline')).length > 0, 'joint plots');
    // The closest approach is marked on the timeline; the mark jumps there.
    if (summary.min_clearance) {
      await page.click('[data-testid=min-clearance-mark]');
      const at = await page.evaluate('window.sscsReport.view.time');
      assert.ok(Math.abs(at - Math.min(summary.min_clearance.t, await page.evaluate('window.sscsReport.view.duration'))) < 1e-6,
        `the min_clearance mark jumps to ${summary.min_clearance.t}, is at ${at}`);
      const title = await page.$eval('[data-testid=min-clearance-mark] title', (e) => e.textContent);
      assert.ok(title.includes(summary.min_clearance.a) && title.includes(summary.min_clearance.b), title);
    }
    // Playing advances time.
    await page.evaluate('window.sscsReport.seek(0)');
    await page.click('[data-testid=play]');
    await new Promise((r) => setTimeout(r, 600));
    assert.ok(await page.evaluate('window.sscsReport.view.time') > 0, 'play moves the time on');
    await page.click('[data-testid=play]');
    await page.evaluate(`window.sscsReport.seek(${events[i].t})`);
    await shot(page, `${basename(file, '.html')}-event`);
    await page.close();
  });
}

for (const file of ['campaign-slots.html', 'campaign-failure.html']) {
  test(`${file}: a Gantt bar per job (failures red) that jumps to its start, the queue and utilization plots, the final state`, async () => {
    const { page, problems } = await open(file);
    const dir = join(out, basename(file, '.html'));
    const summary = JSON.parse(readFileSync(join(dir, 'summary.json'), 'utf8'));
    const rows = readFileSync(join(dir, 'jobs.csv'), 'utf8').trim().split('\n').slice(1);
    const bars = await page.$$eval('svg.gantt rect.job', (rs) => rs.map((r) => ({ job: +r.dataset.job, failed: r.classList.contains('failed'),
      title: r.querySelector('title').textContent })));
    assert.equal(bars.length, rows.length, 'one bar (or mark) a job');
    assert.equal(bars.filter((b) => b.failed).length, summary.campaign.jobs.failed);
    const figures = await page.$eval('[data-testid=campaign-figures]', (e) => e.textContent);
    assert.ok(figures.includes(`${summary.campaign.jobs.done} done`) && figures.includes('makespan'), figures);
    // The last job that started: a click on its bar jumps to its start.
    const jobs = await page.evaluate(`window.SSCS.campaignJobs(${JSON.stringify(readFileSync(join(dir, 'jobs.csv'), 'utf8'))})`);
    const last = jobs.reduce((best, j, k) => (typeof j.start === 'number' && (best < 0 || j.start > jobs[best].start) ? k : best), -1);
    await page.evaluate('window.sscsReport.seek(0)');
    await page.click(`svg.gantt rect.job[data-job="${last}"]`);
    const t = await page.evaluate('window.sscsReport.view.time');
    assert.ok(Math.abs(t - Math.min(jobs[last].start, await page.evaluate('window.sscsReport.view.duration'))) < 1e-6, `at ${t}, the job starts at ${jobs[last].start}`);
    assert.equal(await page.$$eval('section.campaign svg.plot polyline', (p) => p.length), 1 + Object.keys(summary.campaign.devices).length);
    await page.click('[data-testid=final-state]');
    assert.ok(Math.abs(await page.evaluate('window.sscsReport.view.time') - await page.evaluate('window.sscsReport.view.duration')) < 1e-6);
    await shot(page, basename(file, '.html'));
    assert.deepEqual(problems, []);
    await page.close();
  });
}

test('arm-vs-gantry.html: a parameter of words (the scenario files) is an axis of categories with every variant on it', async () => {
  const { page } = await open('arm-vs-gantry.html');
  const results = JSON.parse(readFileSync(join(out, 'arm-vs-gantry', 'results.json'), 'utf8'));
  assert.equal(await page.$eval('[data-testid=plot-x]', (s) => s.value), 'scenario');
  assert.equal((await page.$$('svg.plot circle[data-variant]')).length, results.variants.length);
  const labels = await page.$$eval('svg.plot text', (ts) => ts.map((t) => t.textContent));
  for (const v of results.variants) assert.ok(labels.includes(v.values.scenario), `${v.values.scenario} labels the axis`);
  await page.close();
});

test('aisle-rows.html: one row per variant, one point per variant, a point selects its row', async () => {
  const { page } = await open('aisle-rows.html');
  const results = JSON.parse(readFileSync(join(out, 'aisle-rows', 'results.json'), 'utf8'));
  assert.equal((await page.$$('table.results tbody tr')).length, results.variants.length);
  assert.equal((await page.$$('svg.plot circle[data-variant]')).length, results.variants.length);
  await page.click('svg.plot circle[data-variant="7"]');
  assert.equal(await page.$eval('table.results tbody tr.selected', (tr) => tr.dataset.id), '7');
  // The link of each row reaches the variant's report from where the page is.
  const href = await page.$eval('table.results tbody tr.selected a', (a) => a.getAttribute('href'));
  assert.ok(existsSync(join(out, href)), href);
  await page.select('[data-testid=plot-y]', 'aisle_margin');
  await shot(page, 'aisle-rows-plot');
  await page.close();
});

test('screenshots for docs/reports.md', { skip: !process.env.SSCS_UPDATE_DOCS }, () => {
  const docs = join(dirname(fileURLToPath(import.meta.url)), '..', '..', 'docs', 'img', 'reports');
  mkdirSync(docs, { recursive: true });
  for (const f of ['demo-row-selected', 'ci-branch', 'arm-loads-drum-event', 'store-drum-event', 'aisle-rows-plot', 'devices-closest-Arm'])
    copyFileSync(join(shots, `${f}.png`), join(docs, `${f}.png`));
});

test('hostile.html: names with <!--, </script>, a right-to-left override and 2,000 characters break nothing', async () => {
  const { page, problems } = await open('hostile.html', 'docs');
  assert.deepEqual(problems, []);
  assert.equal(await page.evaluate('window.x'), undefined, 'no script from a name ran');
  const names = await page.$$eval('table.results tbody tr .name', (cells) => cells.map((c) => c.textContent));
  assert.ok(names.includes('the <!-- comment --> rule'), names.join(' | '));
  assert.ok(names.includes('a script </script><script>window.x=1</script> in a name'), names.join(' | '));
  // The override is drawn as a mark, and isolated: the words after the name keep their order.
  assert.ok(names.includes('Keg\u27e8U+202E\u27e9_2 stays low'), names.join(' | '));
  const bodyText = await page.evaluate('document.body.innerText');
  assert.ok(!bodyText.includes('\u202e'), 'no right-to-left override reaches the page');
  // The long name wraps: the table fits its panel and every row's margin is on screen.
  const widths = await page.evaluate(`(() => {
    const t = document.querySelector('table.results'), p = t.closest('.scroll');
    return { table: t.scrollWidth, panel: p.clientWidth, window: window.innerWidth };
  })()`);
  assert.ok(widths.table <= widths.panel + 1, `table ${widths.table} px wide in a ${widths.panel} px panel`);
  const long = await page.$eval('table.results tbody tr .name bdi', (b) => b.getAttribute('title'));
  assert.ok(long.length > 0);
  // --set 'gap=1 <!0' is in the page's data as it was given.
  assert.equal(await page.evaluate('JSON.parse(document.getElementById("sscs-data").textContent).reports[0].set.gap'), '1 <!0');
  await shot(page, 'hostile');
  await page.close();
});

test('hostile-run.html: a run folder named run<!--x shows its run', async () => {
  const { page, problems } = await open('hostile-run.html');
  assert.deepEqual(problems, []);
  assert.equal(await kind(page), 'run');
  assert.ok((await page.$$('table.events tbody tr')).length > 5);
  await page.close();
});

test('hostile-sweep.html: a variant folder that is no relative path is no link, and nothing runs', async () => {
  const { page, problems } = await open('hostile-sweep.html');
  assert.deepEqual(problems, []);
  const hrefs = await page.$$eval('table.results a', (as) => as.map((a) => a.getAttribute('href')));
  assert.ok(hrefs.length > 10, hrefs.join(' '));
  for (const h of hrefs) assert.ok(!/^[a-z][a-z0-9+.-]*:/i.test(h) && !h.startsWith('/'), `link ${h}`);
  assert.ok(!hrefs.some((h) => h.includes('etc')), hrefs.join(' '));
  // Clicking the cell of the javascript: folder runs nothing.
  const cell = await page.$$eval('table.results tbody td', (tds) => tds.findIndex((td) => td.textContent.includes('javascript:')));
  assert.ok(cell >= 0);
  await page.evaluate((i) => document.querySelectorAll('table.results tbody td')[i].click(), cell);
  assert.equal(await page.evaluate('window.x'), undefined);
  await page.close();
});
