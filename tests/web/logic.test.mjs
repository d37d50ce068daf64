// Units of the HTML reports' page logic (src/report/html/logic.js), with node's test runner.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { createRequire } from 'node:module';
const require = createRequire(import.meta.url);
const S = require('../../src/report/html/logic.js');

const report = {
  vault: 'V',
  results: [
    { constraint: 'b', kind: 'bound', severity: 'error', status: 'pass', subject: ['A'], margin: 2, message: 'ok', location: { file: 'v.yaml', line: 3 }, baseline: 'unchanged' },
    { constraint: 'a', kind: 'clearance', severity: 'error', status: 'fail', subject: ['A', 'B'], margin: -0.5, message: 'too close', baseline: 'new' },
    { constraint: 'c', kind: 'bound', severity: 'warning', status: 'fail', subject: ['C'], margin: -1, message: 'warned', baseline: 'still_failing' },
    { constraint: 'd', kind: 'expr', severity: 'error', status: 'error', subject: [], message: 'not a number' },
  ],
  baseline: { removed: [{ constraint: 'gone', was: 'passing' }], renamed: [{ from: 'old b', to: 'b' }] },
};

test('check rows: one per result and per removed constraint, with where and change', () => {
  const rows = S.checkRows([report]);
  assert.equal(rows.length, 5);
  assert.equal(rows[0].where, 'v.yaml:3');
  assert.equal(rows[1].change, 'new');
  assert.equal(rows[2].change, 'still failing');
  assert.equal(rows[0].change, 'renamed');  // its baseline says unchanged: under another name
  assert.equal(rows[0].renamedFrom, 'old b');
  assert.equal(rows[2].status, 'warn');  // a failed warning is a warning, as the text report counts it
  assert.equal(rows[4].status, 'removed');
  assert.equal(rows[4].change, 'removed');
});

test('filters combine status, kind, object and text', () => {
  const rows = S.checkRows([report]);
  assert.deepEqual(S.filterRows(rows, { status: 'fail' }).map((r) => r.constraint), ['a']);
  assert.deepEqual(S.filterRows(rows, { status: 'warn' }).map((r) => r.constraint), ['c']);
  assert.deepEqual(S.filterRows(rows, { kind: 'bound' }).map((r) => r.constraint), ['b', 'c']);
  assert.deepEqual(S.filterRows(rows, { object: 'B' }).map((r) => r.constraint), ['a']);
  assert.deepEqual(S.filterRows(rows, { text: 'TOO' }).map((r) => r.constraint), ['a']);
  assert.deepEqual(S.filterRows(rows, { status: 'fail', severity: 'warning' }).map((r) => r.constraint), []);
  assert.deepEqual(S.filterRows([{ folder: '54-aisle=2m-rows=5', subjects: [] }], { text: 'rows=5' }).length, 1);  // a sweep's folders
  assert.equal(S.filterRows(rows, {}).length, 5);
});

test('sorting: margins numerically with absent last, statuses by gravity, stable', () => {
  const rows = S.checkRows([report]);
  assert.deepEqual(S.sortRows(rows, 'margin', 1).map((r) => r.constraint), ['c', 'a', 'b', 'd', 'gone']);
  assert.deepEqual(S.sortRows(rows, 'margin', -1).map((r) => r.constraint).slice(0, 3), ['b', 'a', 'c']);
  assert.deepEqual(S.sortRows(rows, 'status', 1).map((r) => r.status), ['error', 'fail', 'warn', 'pass', 'removed']);
  assert.deepEqual(S.sortRows(rows, 'constraint', 1).map((r) => r.constraint), ['a', 'b', 'c', 'd', 'gone']);
});

test('numbers: four significant digits, units, non-finite shown as such, absent as a dash', () => {
  assert.equal(S.num(1.23456, 'm'), '1.235 m');
  assert.equal(S.num(0), '0');
  assert.equal(S.num(2.5e-5), '2.500e-5');
  assert.equal(S.num(NaN), 'NaN');
  assert.equal(S.num(undefined), '\u2014');
});

test('times: to the millisecond a run records, whatever their size', () => {
  assert.equal(S.time(12.3456), '12.346');
  assert.equal(S.time(84.818), '84.818');
  assert.equal(S.time(3600.0016), '3600.002');
  assert.equal(S.time(0), '0');
  assert.equal(S.time(undefined), '\u2014');
});

test('CSV: header and numbers, quoted cells', () => {
  const t = S.parseCsv('t,j1,name\n0,1.5,"a,b"\n0.02,2,x\n');
  assert.deepEqual(t.columns, ['t', 'j1', 'name']);
  assert.deepEqual(t.rows, [[0, 1.5, 'a,b'], [0.02, 2, 'x']]);
});

test('scales map the domain and tick at round steps; a flat domain widens', () => {
  const x = S.scale(0, 10, 100, 200);
  assert.equal(x(5), 150);
  assert.deepEqual(x.ticks(5), [0, 2, 4, 6, 8, 10]);
  const flat = S.scale(3, 3, 0, 1);
  assert.ok(flat.domain[0] < 3 && flat.domain[1] > 3);
  assert.ok(Number.isFinite(flat(3)));
  assert.deepEqual(S.extent([3, NaN, -1, 'x', 7]), [-1, 7]);
  assert.equal(S.extent([NaN]), undefined);
});

test('indexAt finds the last sample at or before t', () => {
  const ts = [0, 0.5, 1, 1.5];
  assert.equal(S.indexAt(ts, -1), 0);
  assert.equal(S.indexAt(ts, 0.7), 1);
  assert.equal(S.indexAt(ts, 1), 2);
  assert.equal(S.indexAt(ts, 9), 3);
});

test('steps and events of a run summary', () => {
  const steps = S.stepBreakdown({ steps: [{ index: 0, action: 'move_to', device: 'R', start: 0, end: 1.5 }, { index: 1, action: 'grasp', object: 'D', device: 'R', start: 1.5, end: 1.5 }] });
  assert.deepEqual(steps.map((s) => [s.label, s.duration]), [['1. move_to', 1.5], ['2. grasp D', 0]]);
  // A run that stopped: the summary's null times come from the events; a step never ended has no duration.
  const stopped = S.stepBreakdown({ steps: [{ index: 0, action: 'move_to', start: 0, end: null }, { index: 1, action: 'move_to', start: null, end: null }] },
    [{ t: 0, kind: 'step_start', step: 0 }, { t: 0.715, kind: 'step_end', step: 0 }, { t: 0.715, kind: 'step_start', step: 1 }]);
  assert.deepEqual(stopped.map((s) => [s.start, s.end, s.duration]), [[0, 0.715, 0.715], [0.715, null, null]]);
  assert.deepEqual(S.notableEvents([{ kind: 'step_start' }, { kind: 'collision' }, { kind: 'step_end' }]).map((e) => e.kind), ['collision']);
});

test('sweep rows: parameters as numbers, metrics kept', () => {
  const rows = S.sweepRows({ variants: [{ variant: 0, folder: '00', values: { aisle: '1.5', kind: 'arm' }, status: 'pass', metrics: { capacity: 48 } }] });
  assert.deepEqual(rows[0], { variant: 0, folder: '00', status: 'pass', message: '', passed: undefined, failed: undefined, warnings: undefined, aisle: 1.5, kind: 'arm', capacity: 48 });
});

test('plot axes: numbers on a linear scale, words as categories in natural order', () => {
  const rows = [{ f: 'gantry.yaml', v: 2 }, { f: 'arm.yaml', v: 1 }, { f: 'arm10.yaml', v: NaN }, { f: 'arm2.yaml', v: 3 }];
  const words = S.axis(rows, 'f');
  assert.deepEqual(words.categories, ['arm.yaml', 'arm2.yaml', 'arm10.yaml', 'gantry.yaml']);
  assert.deepEqual(rows.map(words.get), [3, 0, 2, 1]);
  const xs = S.axisScale(words, rows, 0, 400);
  assert.deepEqual(xs.ticks(), [0, 1, 2, 3]);
  assert.equal(xs.label(2), 'arm10.yaml');
  assert.equal(xs(0), 50);
  const numbers = S.axis(rows, 'v');
  assert.equal(numbers.categories, null);
  assert.deepEqual(rows.map(numbers.get), [2, 1, undefined, 3]);
  assert.deepEqual(S.axisScale(numbers, rows, 0, 100).domain, [1, 3]);
});

test('relativeLink: a relative file path is a link, segment by segment encoded; a scheme, an absolute path or //host is none', () => {
  assert.equal(S.relativeLink('v_001/report.json'), 'v_001/report.json');
  assert.equal(S.relativeLink('../sweep/a b/#c?d'), '../sweep/a%20b/%23c%3Fd');
  assert.equal(S.relativeLink('07-aisle=1.1m-rows=3/report.json'), '07-aisle=1.1m-rows=3/report.json');
  assert.equal(S.relativeLink('./x'), './x');
  for (const bad of ['javascript:window.x=99', 'JavaScript:alert(1)', 'data:text/html,x', 'http://host/x', '/etc/passwd',
                     '//host/x', 'a//b', 'a\\b', '', 'v\n1', null, 42]) assert.equal(S.relativeLink(bad), null, String(bad));
  // Encoded, a scheme-like first segment could not run anyway; it is refused so that nothing looks like a link.
  assert.equal(S.relativeLink('x/javascript:y'), 'x/javascript%3Ay');
});

test('showControls: every bidirectional control becomes a visible mark; other text is untouched', () => {
  assert.equal(S.showControls('Keg\u202e_2'), 'Keg\u27e8U+202E\u27e9_2');
  assert.equal(S.showControls('a\u2066b\u2069c\u200fd'), 'a\u27e8U+2066\u27e9b\u27e8U+2069\u27e9c\u27e8U+200F\u27e9d');
  assert.equal(S.showControls('שלום Drum_1 <!-- x -->'), 'שלום Drum_1 <!-- x -->');
  assert.equal(S.showControls(1.5), '1.5');
});

test('splitNames: names found in a message, longest first, the rest kept in order', () => {
  assert.deepEqual(S.splitNames('Keg_22 and Keg_2.height', ['Keg_2', 'Keg_22']), [{ name: 'Keg_22' }, ' and ', { name: 'Keg_2' }, '.height']);
  assert.deepEqual(S.splitNames('nothing here', ['Keg']), ['nothing here']);
  assert.deepEqual(S.splitNames('', ['Keg']), []);
  // Every piece put back together is the message.
  const text = 'A<B and B<A, A and AB';
  const back = S.splitNames(text, ['A', 'B', 'AB']).map((p) => (typeof p === 'string' ? p : p.name)).join('');
  assert.equal(back, text);
});

// A campaign's jobs.csv (tests/data/campaigns/claims.yaml's shape): G1 and G2 share a claim, so
// the jobs run one at a time; Nark_3 never started; a message with a comma is quoted.
const jobsCsv = 'job,object,device,place,ready,start,end,wait,duration,status,message\n'
  + 'a,Mark_1,G1,,0,0,6,0,6,done,\n'
  + 'b,Nark_1,G2,,0,6,12,6,6,done,\n'
  + 'a,Mark_2,G1,,2,12,18,10,6,failed,"G1 cannot reach Mark_2, 0.3 m short"\n'
  + 'b,Nark_3,,,4,,,,,not_started,"planned for G2, which was out"\n';

test('campaign jobs: numbers, empty cells null, quoted messages whole', () => {
  const jobs = S.campaignJobs(jobsCsv);
  assert.equal(jobs.length, 4);
  assert.deepEqual(jobs[1], { job: 'b', object: 'Nark_1', device: 'G2', place: '', ready: 0, start: 6, end: 12, wait: 6, status: 'done', message: '' });
  assert.equal(jobs[2].message, 'G1 cannot reach Mark_2, 0.3 m short');
  assert.equal(jobs[3].start, null);
  assert.equal(jobs[3].device, '');
});

test('campaign queue: a job waits from ready to start, one never started to the end; its peak is queue_max', () => {
  const q = S.queueSeries(S.campaignJobs(jobsCsv), 20);
  // Nark_1 waits 0..6, Mark_2 2..12, Nark_3 4..20 (Mark_1 started when ready: never waited).
  const at = (t) => { let v = 0; for (let k = 0; k < q.xs.length; ++k) if (q.xs[k] <= t) v = q.ys[k]; return v; };
  assert.equal(at(1), 1);
  assert.equal(at(3), 2);
  assert.equal(at(5), 3);
  assert.equal(at(7), 2);
  assert.equal(at(13), 1);
  assert.equal(at(20), 1);
  assert.equal(Math.max(...q.ys), 3);
});

test('campaign utilization: time busy so far over time since the first ready; at the end busy / makespan', () => {
  const jobs = S.campaignJobs(jobsCsv);
  const g1 = S.utilizationSeries(jobs, 'G1', 18, 18);
  assert.equal(g1.xs.length, 18);
  assert.ok(Math.abs(g1.ys[5] - 1) < 1e-12);            // t = 6: busy 0..6
  assert.ok(Math.abs(g1.ys[11] - 6 / 12) < 1e-12);      // t = 12: 6 of 12
  assert.ok(Math.abs(g1.ys[17] - 12 / 18) < 1e-12);     // the end: 12 s busy in 18
  const g2 = S.utilizationSeries(jobs, 'G2', 18, 18);
  assert.ok(Math.abs(g2.ys[17] - 6 / 18) < 1e-12);
});
