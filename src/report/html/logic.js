// sscs HTML reports: the logic that needs no page (tables, filters, series, scales), so that
// node's test runner checks it (tests/web/logic.test.mjs). Loaded as a classic script in the
// report (it sets globalThis.SSCS) and with require() in the tests.
(function (root) {
  'use strict';

  const STATUS_ORDER = { error: 0, fail: 1, warn: 2, pass: 3, skipped: 4 };

  /** The check results of every vault of a check report, flattened, each with its vault. */
  function checkRows(reports) {
    const rows = [];
    reports.forEach((report, vault) => {
      const renamed = new Map((((report.baseline || {}).renamed) || []).map((x) => [x.to, x.from]));
      (report.results || []).forEach((r, i) => {
        let change = baselineChange(r);
        if (renamed.has(r.constraint)) change = 'renamed';
        rows.push({
          id: `${vault}:${i}`,
          vault,
          vaultName: report.vault,
          constraint: r.constraint,
          kind: r.kind,
          severity: r.severity,
          // A failed warning is a warning (the text report counts it so), not a failure.
          status: r.status === 'fail' && r.severity === 'warning' ? 'warn' : r.status,
          renamedFrom: renamed.get(r.constraint),
          subjects: r.subject || [],
          lhs: r.lhs,
          rhs: r.rhs,
          margin: r.margin,
          unit: r.unit || '',
          message: r.message || '',
          closest: r.closest || null,
          where: r.location ? `${r.location.file}:${r.location.line}` : '',
          change,
        });
      });
      const removed = (report.baseline && report.baseline.removed) || [];
      removed.forEach((r, i) => {
        rows.push({
          id: `${vault}:removed:${i}`, vault, vaultName: report.vault, constraint: r.constraint, kind: '', severity: '',
          status: 'removed', subjects: [], lhs: undefined, rhs: undefined, margin: undefined, unit: '',
          message: `removed (it was ${r.was})`, where: '', change: 'removed',
        });
      });
    });
    return rows;
  }

  /** What a result's baseline entry says changed: new, fixed, still failing, renamed or ''. */
  function baselineChange(r) {
    const b = r.baseline;
    if (!b) return '';
    if (typeof b === 'string') return b.replace(/_/g, ' ');
    if (b.change) return String(b.change).replace(/_/g, ' ');
    if (b.status) return String(b.status).replace(/_/g, ' ');
    return '';
  }

  /** Rows kept by a filter: {status, kind, severity, change, text, object} ('' or absent: any). */
  function filterRows(rows, f) {
    const text = (f.text || '').trim().toLowerCase();
    return rows.filter((r) =>
      (!f.status || r.status === f.status) &&
      (!f.kind || r.kind === f.kind) &&
      (!f.severity || r.severity === f.severity) &&
      (!f.change || r.change === f.change) &&
      (!f.object || r.subjects.includes(f.object)) &&
      (!text || [r.constraint, r.kind, r.message, r.where, r.folder, (r.subjects || []).join(' ')].join(' ').toLowerCase().includes(text)));
  }

  /** Compares two cells: numbers numerically (absent last), statuses by gravity, else text. */
  function compareCells(a, b, key) {
    if (key === 'status') return (STATUS_ORDER[a] ?? 9) - (STATUS_ORDER[b] ?? 9);
    const na = typeof a === 'number' && Number.isFinite(a), nb = typeof b === 'number' && Number.isFinite(b);
    if (na || nb) {
      if (!na) return 1;
      if (!nb) return -1;
      return a - b;
    }
    return String(a ?? '').localeCompare(String(b ?? ''), undefined, { numeric: true });
  }

  const absent = (v) => v === undefined || v === null || v === '' || (Array.isArray(v) && !v.length);

  /** Rows sorted by `key` (a row field), `dir` 1 or -1, rows without a value last either way; stable. */
  function sortRows(rows, key, dir) {
    return rows.map((r, i) => [r, i]).sort((x, y) => {
      const a = x[0][key], b = y[0][key];
      if (absent(a) !== absent(b)) return absent(a) ? 1 : -1;
      const c = compareCells(a, b, key);
      return c !== 0 ? c * dir : x[1] - y[1];
    }).map((p) => p[0]);
  }

  /** The distinct values of a field, sorted, for a filter's options. */
  function distinct(rows, key) {
    return [...new Set(rows.map((r) => r[key]).filter((v) => v !== '' && v !== undefined))].sort();
  }

  /** A number as a report shows it (4 significant digits; none: an em dash). */
  function num(v, unit) {
    if (typeof v !== 'number') return '\u2014';
    if (!Number.isFinite(v)) return String(v);
    const s = Math.abs(v) >= 1e5 || (v !== 0 && Math.abs(v) < 1e-3) ? v.toExponential(3) : String(+v.toPrecision(4));
    return unit ? `${s} ${unit}` : s;
  }

  /** A time in seconds as a run records it: to the millisecond (12.346), not to 4 digits (12.35). */
  function time(t) {
    return typeof t === 'number' && Number.isFinite(t) ? String(+t.toFixed(3)) : '\u2014';
  }

  /** A CSV text (header row, comma-separated numbers or words) as {columns, rows}. */
  function parseCsv(text) {
    const lines = text.split(/\r?\n/).filter((l) => l.length);
    if (!lines.length) return { columns: [], rows: [] };
    const columns = splitCsvLine(lines[0]);
    const rows = lines.slice(1).map((l) => splitCsvLine(l).map((c) => (c !== '' && !isNaN(+c) ? +c : c)));
    return { columns, rows };
  }

  function splitCsvLine(line) {
    const out = [];
    let cell = '', quoted = false;
    for (let i = 0; i < line.length; ++i) {
      const c = line[i];
      if (quoted) {
        if (c === '"' && line[i + 1] === '"') { cell += '"'; ++i; } else if (c === '"') quoted = false; else cell += c;
      } else if (c === '"') quoted = true;
      else if (c === ',') { out.push(cell); cell = ''; } else cell += c;
    }
    out.push(cell);
    return out;
  }

  /** A linear scale from [d0, d1] to [r0, r1] with `nice` ticks; an empty or flat domain widens. */
  function scale(d0, d1, r0, r1) {
    if (!Number.isFinite(d0) || !Number.isFinite(d1)) { d0 = 0; d1 = 1; }
    if (d0 === d1) { d0 -= Math.abs(d0) * 0.05 || 0.5; d1 += Math.abs(d1) * 0.05 || 0.5; }
    const f = (v) => r0 + ((v - d0) / (d1 - d0)) * (r1 - r0);
    f.domain = [d0, d1];
    f.ticks = (n = 5) => {
      const step0 = (d1 - d0) / n, mag = Math.pow(10, Math.floor(Math.log10(step0)));
      const step = [1, 2, 5, 10].map((m) => m * mag).find((s) => s >= step0);
      const out = [];
      for (let v = Math.ceil(d0 / step) * step; v <= d1 + step * 1e-9; v += step) out.push(+v.toPrecision(12));
      return out;
    };
    return f;
  }

  /** [min, max] of finite values (undefined when none). */
  function extent(values) {
    let lo = Infinity, hi = -Infinity;
    for (const v of values) if (typeof v === 'number' && Number.isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    return lo <= hi ? [lo, hi] : undefined;
  }

  /** The index of the last time <= t in increasing `times` (0 before the first). */
  function indexAt(times, t) {
    let lo = 0, hi = times.length - 1;
    if (hi < 0 || t <= times[0]) return 0;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (times[mid] <= t) lo = mid; else hi = mid - 1;
    }
    return lo;
  }

  /** Per-step durations of a run summary, in order: {label, device, start, end, duration}. A
   *  time the summary leaves null (a run that stopped) is taken from the step's events; a step
   *  that never ended has no duration (null), never 0. */
  function stepBreakdown(summary, events = []) {
    const at = (kind, index) => { const e = events.find((x) => x.kind === kind && x.step === index); return e ? e.t : null; };
    return (summary.steps || []).map((s) => {
      const start = s.start ?? at('step_start', s.index), end = s.end ?? at('step_end', s.index);
      return {
        label: `${s.index + 1}. ${s.action}${s.object ? ' ' + s.object : ''}`,
        device: s.device || '',
        start,
        end,
        duration: typeof start === 'number' && typeof end === 'number' ? end - start : null,
      };
    });
  }

  /** Events worth a mark on the timeline (not every step start and end). */
  function notableEvents(events) {
    return events.filter((e) => e.kind !== 'step_start' && e.kind !== 'step_end');
  }

  /** A sweep's variants as rows: {variant, folder, status, message, <parameter>: number, <metric>: number}. */
  function sweepRows(results) {
    return (results.variants || []).map((v) => {
      const row = { variant: v.variant, folder: v.folder, status: v.status, message: v.message || '',
                    passed: v.passed, failed: v.failed, warnings: v.warnings };
      for (const [k, x] of Object.entries(v.values || {})) row[k] = x !== '' && !isNaN(+x) ? +x : x;
      for (const [k, x] of Object.entries(v.metrics || {})) row[k] = x;
      for (const k of ['cycle_time', 'collisions']) if (k in v) row[k] = v[k];  // a simulated sweep's columns
      return row;
    });
  }

  /** How a column goes on a plot's axis: numbers as they are; a column of words (a sweep's
   *  alternative files, an enum) as categories at 0, 1, 2, ... in natural order. */
  function axis(rows, key) {
    const words = rows.map((r) => r[key]).filter((v) => typeof v === 'string' && v !== '');
    if (!words.length) return { categories: null, get: (r) => (typeof r[key] === 'number' && Number.isFinite(r[key]) ? r[key] : undefined) };
    const categories = [...new Set(words)].sort((a, b) => a.localeCompare(b, undefined, { numeric: true }));
    return { categories, get: (r) => { const i = categories.indexOf(String(r[key])); return i >= 0 ? i : undefined; } };
  }

  /** A scale for an axis: linear over the numbers' extent, or one step per category (ticks
   *  at each, labelled with its name). */
  function axisScale(ax, rows, r0, r1) {
    if (!ax.categories) {
      const e = extent(rows.map(ax.get)) || [0, 1];
      return scale(e[0], e[1], r0, r1);
    }
    const f = scale(-0.5, ax.categories.length - 0.5, r0, r1);
    f.ticks = () => ax.categories.map((_, i) => i);
    f.label = (t) => ax.categories[t];
    return f;
  }

  /** A link to `path` only when it is a relative file path: no scheme (`javascript:`, `data:`,
   *  `http:`), no leading `/` or `\\`, no empty segment (`//host`); what a URL would read
   *  otherwise escaped (a folder named `a?b#c` is a folder). Else null: no link at all. A sweep's results.json is an
   *  artifact anyone can edit. */
  function relativeLink(path) {
    if (typeof path !== 'string' || path === '' || /[\u0000-\u001f\\]/.test(path)) return null;
    const parts = path.split('/');
    if (parts[0] === '' || /^[a-z][a-z0-9+.-]*:/i.test(parts[0])) return null;
    if (parts.some((p) => p === '')) return null;
    // Only what a URL reads otherwise (%, #, ?, :, spaces, quotes, brackets) is escaped.
    return parts.map((p) => p.replace(/[%#?:\s"'<>\\^`{|}]/g, (c) => encodeURIComponent(c))).join('/');
  }

  // Bidirectional controls (embeddings, overrides, isolates, marks): a name holding one could
  // reorder the text drawn after it. Shown as visible marks instead, like a code review shows them.
  const BIDI_CONTROLS = /[\u061c\u200e\u200f\u202a-\u202e\u2066-\u2069]/g;
  /** `text` with every bidirectional control character replaced by a visible ⟨U+XXXX⟩. */
  function showControls(text) {
    return String(text).replace(BIDI_CONTROLS, (c) => `\u27e8U+${c.charCodeAt(0).toString(16).toUpperCase().padStart(4, '0')}\u27e9`);
  }

  /** `text` cut into pieces, each a plain string or {name} where one of `names` occurs (longest
   *  first), so that the page can isolate each name's direction (<bdi>) from the words around it. */
  function splitNames(text, names) {
    const wanted = [...new Set((names || []).filter((n) => typeof n === 'string' && n !== ''))].sort((a, b) => b.length - a.length);
    const out = [];
    let rest = String(text ?? '');
    while (rest !== '') {
      let at = -1, found = null;
      for (const n of wanted) {
        const i = rest.indexOf(n);
        if (i >= 0 && (at < 0 || i < at || (i === at && n.length > found.length))) { at = i; found = n; }
      }
      if (at < 0) { out.push(rest); break; }
      if (at > 0) out.push(rest.slice(0, at));
      out.push({ name: found });
      rest = rest.slice(at + found.length);
    }
    return out;
  }

  /** A campaign's jobs.csv as rows: numbers where the file has them, null where it leaves a cell empty. */
  function campaignJobs(text) {
    const t = parseCsv(text || '');
    const col = (name) => t.columns.indexOf(name);
    const value = (r, name) => { const v = r[col(name)]; return v === '' || v === undefined ? null : v; };
    return t.rows.map((r) => ({ job: String(value(r, 'job') ?? ''), object: String(value(r, 'object') ?? ''), device: String(value(r, 'device') ?? ''),
      place: String(value(r, 'place') ?? ''), ready: value(r, 'ready'), start: value(r, 'start'), end: value(r, 'end'), wait: value(r, 'wait'),
      status: String(value(r, 'status') ?? ''), message: String(value(r, 'message') ?? '') }));
  }

  /** The queue's length over time, as summary.json's queue_max counts it: a job joins when ready
   *  and leaves when it starts (one started the moment it was ready never waited); one never
   *  started waits to `end`. A step function: {xs, ys}. */
  function queueSeries(jobs, end) {
    const changes = [];
    for (const j of jobs) {
      if (typeof j.ready !== 'number') continue;
      const started = typeof j.start === 'number';
      if (started && j.start <= j.ready + 1e-9) continue;
      changes.push([j.ready, +1]);
      if (started) changes.push([j.start, -1]);
    }
    changes.sort((a, b) => a[0] - b[0] || a[1] - b[1]);  // at one time, starts before arrivals
    const xs = [0], ys = [0];
    let n = 0;
    for (const [t, d] of changes) {
      xs.push(t); ys.push(n);
      n = Math.max(0, n + d);
      xs.push(t); ys.push(n);
    }
    xs.push(Math.max(end, xs[xs.length - 1])); ys.push(n);
    return { xs, ys };
  }

  /** A device's utilization so far at `points` times from the campaign's first ready job to `end`:
   *  its jobs' time busy (start to end) up to t over the time since the first job was ready. At
   *  the end it is summary.json's utilization. */
  function utilizationSeries(jobs, device, end, points = 120) {
    const readies = jobs.map((j) => j.ready).filter((t) => typeof t === 'number');
    const first = readies.length ? Math.min(...readies) : 0;
    const mine = jobs.filter((j) => j.device === device && typeof j.start === 'number' && typeof j.end === 'number');
    const xs = [], ys = [];
    for (let k = 1; k <= points; ++k) {
      const t = first + ((end - first) * k) / points;
      let busy = 0;
      for (const j of mine) busy += Math.max(0, Math.min(t, j.end) - j.start);
      xs.push(t);
      ys.push(t > first ? busy / (t - first) : 0);
    }
    return { xs, ys };
  }

  const api = { campaignJobs, queueSeries, utilizationSeries, relativeLink, showControls, splitNames, checkRows, baselineChange, filterRows, compareCells, sortRows, distinct, num, time, parseCsv, scale, extent,
                indexAt, stepBreakdown, notableEvents, sweepRows, axis, axisScale };
  root.SSCS = Object.assign(root.SSCS || {}, api);
  if (typeof module === 'object' && module.exports) module.exports = api;
})(typeof globalThis !== 'undefined' ? globalThis : this);
