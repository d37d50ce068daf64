// sscs HTML reports: the page. One of three kinds, from the data sscs inlined
// (<script id="sscs-data">): a check (the JSON report of each vault and its model), a run (its
// summary, events, trajectories and animated model), a sweep (its results). window.sscsReport
// exposes the page's state to the browser tests (tests/web/reports.test.mjs).
(function (root) {
  'use strict';
  const S = root.SSCS;
  const RED = 0xd62728, ORANGE = 0xff7f0e, YELLOW = 0xe0b000, BLUE = 0x1f77b4, GREEN = 0x2ca02c;
  const STATUS_COLOUR = { pass: '#2ca02c', fail: '#d62728', error: '#8c1c13', warn: '#ff9f1c', removed: '#7f7f7f' };

  function el(tag, attrs = {}, ...children) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs)) {
      if (k === 'class') e.className = v;
      else if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
      else if (v !== undefined && v !== null && v !== false) e.setAttribute(k, v === true ? '' : v);
    }
    for (const c of children.flat(Infinity)) if (c !== null && c !== undefined) e.append(c instanceof Node ? c : S.showControls(c));
    return e;
  }
  /** A name drawn apart from the text around it: its direction isolated (<bdi>), wrapped where
   *  it is long, whole on hover. */
  function nameEl(name) { return el('bdi', { class: 'name-text', title: S.showControls(name) }, name); }
  /** A message with each of `names` in it isolated (a right-to-left name cannot reorder the
   *  words after it). */
  function withNames(text, names) {
    return S.splitNames(text, names).map((piece) => (typeof piece === 'string' ? piece : nameEl(piece.name)));
  }
  const svgNS = 'http://www.w3.org/2000/svg';
  function svg(tag, attrs = {}, ...children) {
    const e = document.createElementNS(svgNS, tag);
    for (const [k, v] of Object.entries(attrs)) {
      if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
      else e.setAttribute(k, v);
    }
    for (const c of children.flat(Infinity)) if (c) e.append(c instanceof Node ? c : document.createTextNode(S.showControls(c)));
    return e;
  }
  function chip(status, text) { return el('span', { class: `chip ${status}` }, text ?? status); }
  function model(id) { const e = id && document.getElementById(id); return e ? e.textContent : null; }

  // ---- a sortable, filterable table ------------------------------------------------------------
  class Table {
    constructor(columns, rows, { onSelect, rowClass, onFilter } = {}) {
      this.columns = columns;  // [{key, label, render?(row), numeric?}]
      this.rows = rows;
      this.filter = {};
      this.sort = { key: null, dir: 1 };
      this.onSelect = onSelect || (() => {});
      this.onFilter = onFilter || (() => {});
      this.rowClass = rowClass || (() => '');
      this.selected = null;
      this.limit = 500;  // rows drawn at first
      this.element = el('table', { class: 'results', 'data-testid': 'results' });
      this.head = el('thead');
      this.body = el('tbody');
      this.element.append(this.head, this.body);
      const tr = el('tr');
      for (const c of columns)
        tr.append(el('th', { 'data-key': c.key, class: c.numeric ? 'num' : '', onclick: () => this.sortBy(c.key) }, c.label));
      this.head.append(tr);
      this.draw();
    }
    sortBy(key) {
      this.sort = { key, dir: this.sort.key === key ? -this.sort.dir : 1 };
      for (const th of this.head.querySelectorAll('th'))
        th.dataset.sorted = th.dataset.key === key ? (this.sort.dir > 0 ? 'asc' : 'desc') : '';
      this.draw();
    }
    setFilter(f) { this.filter = Object.assign({}, this.filter, f); this.draw(); this.onFilter(); }
    visible() {
      const kept = S.filterRows(this.rows, this.filter);
      return this.sort.key ? S.sortRows(kept, this.sort.key, this.sort.dir) : kept;
    }
    draw() {
      this.body.replaceChildren();
      const visible = this.visible();
      // A report of 10,000 checks: its first rows drawn (the selected one too), the rest on request;
      // drawing every row took a browser seconds at each update.
      const drawn = visible.length > this.limit ? visible.slice(0, this.limit) : visible;
      if (this.selected && drawn !== visible && !drawn.includes(this.selected) && visible.includes(this.selected)) drawn.push(this.selected);
      for (const row of drawn) {
        const tr = el('tr', { 'data-id': row.id, 'data-subjects': (row.subjects || []).join('|'), class: `${this.rowClass(row)}${row === this.selected ? ' selected' : ''}`,
                              onclick: () => this.select(row) });
        for (const c of this.columns) tr.append(el('td', { class: c.numeric ? 'num' : '' }, c.render ? c.render(row) : row[c.key]));
        this.body.append(tr);
      }
      if (drawn.length < visible.length)
        this.body.append(el('tr', { class: 'more' }, el('td', { colspan: this.columns.length },
          el('button', { 'data-testid': 'more-rows', onclick: () => { this.limit = Infinity; this.draw(); } },
            `show the other ${visible.length - drawn.length} rows`), ' (or filter or search: every row is searched)')));
      if (this.counter) this.counter.textContent = `${visible.length} of ${this.rows.length}`;
    }
    select(row) {
      this.selected = row;
      if (row && ![...this.body.children].some((tr) => tr.dataset.id === row.id)) this.draw();  // a row past those drawn
      for (const tr of this.body.children) tr.classList.toggle('selected', tr.dataset.id === (row && row.id));
      this.onSelect(row);
    }
    /** Filter controls: a select per field in `fields`, a search box, a count. */
    controls(fields, placeholder = 'search constraints, objects, messages') {
      const bar = el('div', { class: 'filters' });
      for (const [key, label] of fields) {
        const values = S.distinct(this.rows, key);
        if (values.length < 2 && key !== 'status') continue;
        bar.append(el('label', {}, `${label} `, el('select', { 'data-filter': key, onchange: (e) => this.setFilter({ [key]: e.target.value }) },
          el('option', { value: '' }, 'all'), values.map((v) => el('option', { value: v }, v)))));
      }
      bar.append(el('input', { type: 'search', placeholder, 'data-filter': 'text',
                               oninput: (e) => this.setFilter({ text: e.target.value }) }));
      this.counter = el('span', { class: 'count' });
      bar.append(this.counter);
      this.draw();
      return bar;
    }
  }

  // ---- plots (SVG) -------------------------------------------------------------------------------
  /** Lines of `series` [{name, xs, ys, colour}] in an SVG; returns {svg, cursor(x)}. */
  function linePlot(series, { width = 560, height = 200, xLabel = '', yLabel = '', onClick } = {}) {
    const m = { l: 56, r: 12, t: 10, b: 34 };
    const xe = S.extent(series.flatMap((s) => s.xs)) || [0, 1], ye = S.extent(series.flatMap((s) => s.ys)) || [0, 1];
    const x = S.scale(xe[0], xe[1], m.l, width - m.r), y = S.scale(ye[0], ye[1], height - m.b, m.t);
    const g = svg('svg', { viewBox: `0 0 ${width} ${height}`, class: 'plot', width, height });
    axes(g, x, y, width, height, m, xLabel, yLabel);
    const palette = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2', '#17becf'];
    series.forEach((s, i) => {
      const pts = s.xs.map((xv, k) => (Number.isFinite(s.ys[k]) ? `${x(xv).toFixed(1)},${y(s.ys[k]).toFixed(1)}` : null)).filter(Boolean);
      g.append(svg('polyline', { points: pts.join(' '), fill: 'none', stroke: s.colour || palette[i % palette.length], 'stroke-width': 1.5 }));
    });
    const legend = svg('g', { class: 'legend' });
    series.forEach((s, i) => legend.append(svg('text', { x: m.l + 6 + i * 62, y: m.t + 10, style: `fill: ${s.colour || palette[i % palette.length]}; font-weight: 600` }, s.name)));
    g.append(legend);
    const cursor = svg('line', { y1: m.t, y2: height - m.b, class: 'cursor' });
    g.append(cursor);
    if (onClick) g.addEventListener('click', (e) => {
      const r = g.getBoundingClientRect();
      const px = ((e.clientX - r.left) / r.width) * width;
      onClick(x.domain[0] + ((px - m.l) / (width - m.l - m.r)) * (x.domain[1] - x.domain[0]));
    });
    return { svg: g, cursor: (v) => { cursor.setAttribute('x1', x(v)); cursor.setAttribute('x2', x(v)); } };
  }

  function axes(g, x, y, width, height, m, xLabel, yLabel) {
    for (const t of x.ticks(6)) {
      g.append(svg('line', { x1: x(t), x2: x(t), y1: m.t, y2: height - m.b, class: 'gridline' }));
      g.append(svg('text', { x: x(t), y: height - m.b + 14, 'text-anchor': 'middle' }, x.label ? x.label(t) : S.num(t)));
    }
    for (const t of y.ticks(4)) {
      g.append(svg('line', { x1: m.l, x2: width - m.r, y1: y(t), y2: y(t), class: 'gridline' }));
      g.append(svg('text', { x: m.l - 4, y: y(t) + 4, 'text-anchor': 'end' }, y.label ? y.label(t) : S.num(t)));
    }
    g.append(svg('text', { x: (m.l + width - m.r) / 2, y: height - 4, 'text-anchor': 'middle', class: 'label' }, xLabel));
    g.append(svg('text', { x: 12, y: (m.t + height - m.b) / 2, 'text-anchor': 'middle', class: 'label',
                           transform: `rotate(-90 12 ${(m.t + height - m.b) / 2})` }, yLabel));
  }

  // ---- the page ----------------------------------------------------------------------------------
  function header(title, ...items) {
    return el('header', {}, el('h1', {}, title), el('div', { class: 'summary' }, items));
  }

  // The 3D view of the page before a rebuild in place (sscs serve): taken by the first viewPanel,
  // with the model it shows when the server sent a save's changes into it (spareKeepsModel).
  let spare = null, spareKeepsModel = false;

  function viewPanel(modelId, opts) {
    const text = model(modelId);
    if (spare && (text || spareKeepsModel)) {  // the same canvas, camera and switches, with the new model
      const view = spare;
      spare = null;
      view.onPick = (opts && opts.onPick) || (() => {});
      view.onTime = (opts && opts.onTime) || (() => {});
      if (!spareKeepsModel) view.replaceModel(text);  // (else the model was patched in the view: sscs serve)
      spareKeepsModel = false;
      return { panel: el('section', { class: 'panel3d' }, view.box), box: view.box, view };
    }
    if (spare) { spare.dispose(); spare = null; }
    const box = el('div', { class: 'view3d' });
    const panel = el('section', { class: 'panel3d' }, box);
    if (!text) {
      box.append(el('p', { class: 'note' }, 'No 3D model in this report (its vault could not be read).'));
      return { panel, view: null };
    }
    const view = new S.View3D(box, text, opts);
    view.box = box;
    // Over the view: back to the whole scene, and walls see-through (on: they hide the racks).
    const xray = el('input', { type: 'checkbox', checked: true, 'data-testid': 'xray', onchange: (e) => view.setXray(e.target.checked) });
    box.append(el('div', { class: 'overlay' }, el('button', { 'data-testid': 'frame-all', onclick: () => view.frameAll() }, 'whole scene'),
                  el('label', {}, xray, ' see-through walls')));
    view.ready.then(() => view.setXray(true));
    return { panel, box, view };
  }

  function checkPage(data, app) {
    const reports = data.reports;
    const rows = S.checkRows(reports);
    const failing = (r) => r.status === 'fail' || r.status === 'error';
    const totals = { pass: 0, fail: 0, error: 0, warn: 0 };
    for (const r of rows) if (totals[r.status] !== undefined) totals[r.status]++;  // a failed warning is 'warn'
    const baseline = reports.map((r) => r.baseline).filter(Boolean);
    const hasBaseline = baseline.length > 0;
    app.append(header(`sscs check \u2014 ${reports.map((r) => r.vault).join(', ')}`,
      chip('pass', `${totals.pass} pass`), chip('fail', `${totals.fail} fail`), totals.error ? chip('error', `${totals.error} error`) : null,
      totals.warn ? chip('warn', `${totals.warn} warnings`) : null,
      hasBaseline ? el('span', { class: 'baseline-summary', 'data-testid': 'baseline' },
        baseline.map((b) => `against ${b.file}: ${b.new} new, ${b.fixed} fixed, ${b.still_failing} still failing` +
          `${(b.renamed || []).length ? `, ${b.renamed.length} renamed` : ''}${(b.removed || []).length ? `, ${b.removed.length} removed` : ''}`).join('; ')) : null,
      (data.notes || []).map((n) => el('div', { class: 'note warning', 'data-testid': 'note' }, n))));
    let view = null, vaultShown = 0;
    const objectPanel = el('div', { class: 'object-panel', 'data-testid': 'object-panel' }, el('p', { class: 'note' }, 'Click an object to list its constraints.'));
    const colours = (vault, selected) => {
      const map = {};
      for (const r of rows) if (r.vault === vault && r.status === 'warn') for (const s of r.subjects) map[s] = YELLOW;
      for (const r of rows) if (r.vault === vault && failing(r)) for (const s of r.subjects) map[s] = RED;
      if (hasBaseline) for (const r of rows) if (r.vault === vault && r.change === 'new') for (const s of r.subjects) map[s] = ORANGE;
      if (hasBaseline) for (const r of rows) if (r.vault === vault && r.change === 'fixed') for (const s of r.subjects) if (!map[s]) map[s] = GREEN;
      if (selected) for (const s of selected.subjects) map[s] = BLUE;
      return map;
    };
    const columns = [
      { key: 'status', label: 'Status', render: (r) => chip(r.status) },
      hasBaseline ? { key: 'change', label: 'Change', render: (r) => (r.change ? el('span', { class: `change ${r.change.replace(/ /g, '-')}` },
        r.renamedFrom ? `renamed (was ${r.renamedFrom})` : r.change) : '') } : null,
      reports.length > 1 ? { key: 'vaultName', label: 'Vault' } : null,
      { key: 'constraint', label: 'Constraint', render: (r) => [el('div', { class: 'name' }, nameEl(r.constraint)),
        el('div', { class: 'message' }, withNames(r.message, [...r.subjects, r.constraint])),
        r.closest ? el('div', { class: 'closest', 'data-testid': 'closest', title: 'select the row: the 3D view draws the device at this pose, and a red rod from its tool to the target' },
          'closest pose: ', (r.closest.joints || []).map((j) => `${j.name} ${S.num(Math.abs(j.value) < 1e-6 ? 0 : j.value, j.unit)}`).join(', ')) : null,
        r.where ? el('code', { class: 'where' }, r.where) : null] },
      { key: 'kind', label: 'Kind' },
      { key: 'severity', label: 'Severity' },
      { key: 'subjects', label: 'Objects', render: (r) => (r.subjects.length > 4
        ? el('span', { title: r.subjects.join(', ') }, r.subjects.slice(0, 3).flatMap((n, i) => (i ? [', ', nameEl(n)] : [nameEl(n)])), ` and ${r.subjects.length - 3} more`)
        : r.subjects.flatMap((n, i) => (i ? [', ', nameEl(n)] : [nameEl(n)]))) },
      { key: 'lhs', label: 'Value', numeric: true, render: (r) => S.num(r.lhs, r.unit) },
      { key: 'rhs', label: 'Limit', numeric: true, render: (r) => S.num(r.rhs, r.unit) },
      { key: 'margin', label: 'Margin', numeric: true, render: (r) => S.num(r.margin, r.unit) },
    ].filter(Boolean);
    const table = new Table(columns, rows, {
      rowClass: (r) => r.status,
      onSelect: (r) => {
        if (!r) return;
        if (r.vault !== vaultShown) showVault(r.vault);
        if (view) {
          const v = view;
          v.ready.then(() => {
            v.setHighlights(colours(r.vault, r));
            v.showClosest(r.closest && r.subjects[0], r.closest);  // why it cannot reach (else: back as it stands)
            drawReach(v, r);
            if (r.subjects.length) v.frameObjects(r.subjects);
          });
        }
      },
    });
    const filters = table.controls([['status', 'Status'], ['kind', 'Kind'], ['severity', 'Severity'], ...(hasBaseline ? [['change', 'Change']] : [])]);
    const listObject = (name) => {
      objectPanel.replaceChildren();
      if (!name) { objectPanel.append(el('p', { class: 'note' }, 'Nothing there: click an object.')); table.setFilter({ object: '' }); return; }
      const own = rows.filter((r) => r.vault === vaultShown && r.subjects.includes(name));
      objectPanel.append(el('h3', {}, nameEl(name)), own.length
        ? el('ul', {}, own.map((r) => el('li', {}, chip(r.status), ' ', el('a', { href: '#', onclick: (e) => { e.preventDefault(); table.select(r); } }, nameEl(r.constraint)), ' \u2014 ', withNames(r.message, [...r.subjects, r.constraint]))))
        : el('p', { class: 'note' }, 'No constraint names it.'),
        el('button', { onclick: () => { table.setFilter({ object: '' }); objectPanel.replaceChildren(el('p', { class: 'note' }, 'Click an object to list its constraints.')); } }, 'show every row'));
      table.setFilter({ object: name });
      view && view.setHighlights(Object.assign(colours(vaultShown), { [name]: BLUE }));
    };
    // One 3D view, of the vault whose rows are looked at (a check of several vaults switches).
    const panel3d = el('section', { class: 'panel3d-holder' });
    const vaultSelect = reports.length > 1 ? el('select', { 'data-testid': 'vault', onchange: (e) => showVault(+e.target.value) },
      reports.map((r, i) => el('option', { value: i }, r.vault))) : null;
    // Where the devices reach: a failed reach row's device always, every device's with the switch.
    const reachOf = (i) => (data.reach && data.reach[i]) || {};
    function drawReach(v, row) {
      const clouds = reachOf(vaultShown), shown = {};
      const all = v.box && v.box.querySelector('[data-testid=reach]');
      if (all && all.checked) Object.assign(shown, clouds);
      if (row && row.closest && clouds[row.subjects[0]]) shown[row.subjects[0]] = clouds[row.subjects[0]];
      v.showReach(shown);
    }
    function showVault(i) {
      if (view) view.dispose();
      vaultShown = i;
      if (vaultSelect) vaultSelect.value = String(i);
      const v = viewPanel(data.models[i], { onPick: listObject });
      view = v.view;
      const overlay = v.box && v.box.querySelector('.overlay');
      if (overlay) {
        let toggle = overlay.querySelector('[data-testid=reach]');
        if (!toggle && Object.keys(reachOf(i)).length) {
          toggle = el('input', { type: 'checkbox', 'data-testid': 'reach' });
          overlay.append(el('label', { title: 'dots where each device\'s tool reaches within its joint limits (collisions and orientation aside)' }, toggle, ' where devices reach'));
        }
        if (toggle) {
          toggle.parentElement.hidden = !Object.keys(reachOf(i)).length;
          toggle.onchange = () => view && view.ready.then((w) => drawReach(w, table.selected));
        }
      }
      page.view = view;
      panel3d.replaceChildren(v.panel);
      if (vaultSelect) v.panel.prepend(el('label', { class: 'vault-choice' }, '3D view of ', vaultSelect));
      v.panel.append(objectPanel);
      if (view) view.ready.then(() => { view.setHighlights(colours(i)); drawReach(view, null); });
    }
    const page = { kind: 'check', table, view, rows, listObject, showVault, drawReach };
    app.append(el('main', { class: 'check' }, el('section', { class: 'table-panel' }, filters, el('div', { class: 'scroll' }, table.element)), panel3d));
    showVault(0);
    return page;
  }

  function runPage(data, app) {
    const sum = data.summary;
    const events = data.events || [];
    const steps = S.stepBreakdown(sum, events);
    const mc = sum.min_clearance;
    const statusClass = sum.status === 'ok' ? 'pass' : sum.status === 'violations' ? 'fail' : 'error';
    const timeText = el('span', { class: 'time', 'data-testid': 'time' }, '0.00 s');
    app.append(header(`sscs simulate \u2014 ${sum.scenario} (${sum.vault})`, chip(statusClass, sum.status),
      el('span', {}, `cycle time ${typeof sum.cycle_time === 'number' ? `${S.time(sum.cycle_time)} s` : S.num(sum.cycle_time)}`),  // to the ms, as simulate prints it
      // As docs/simulation.md defines it; below zero it is how deep they went into each other.
      mc ? el('a', { href: '#', 'data-testid': 'min-clearance',
        title: 'closest approach over the run (below zero: the deepest penetration). Not counted: rooms; a load and the stack it rides on; '
          + 'a device and the loads it handles, down to 5 mm deep; a load and what it was lifted off or set down on, only during the move '
          + 'that lifts it or sets it down, down to 5 mm deep',
        onclick: (e) => { e.preventDefault(); seek(mc.t); view && view.frameObjects([mc.a.split('.')[0], mc.b.split('.')[0]]); } },
        mc.distance < 0 ? `penetration ${S.num(-mc.distance, 'm')} between ` : `minimum clearance ${mc.certified ? '(certified) ' : ''}${S.num(mc.distance, 'm')} between `,
        nameEl(mc.a), ' and ', nameEl(mc.b), ` at ${S.time(mc.t)} s`) : null,
      el('span', {}, `${Object.entries(sum.events || {}).map(([k, n]) => `${n} ${k}`).join(', ')}`)));
    const v = viewPanel(data.model, { onTime: (t) => onTime(t) });
    const view = v.view;
    const duration = Math.max(sum.simulated_time || 0, sum.cycle_time || 0, view ? view.duration : 0);
    const scrub = el('input', { type: 'range', min: 0, max: duration, step: 'any', value: 0, 'data-testid': 'scrub',
                                oninput: (e) => seek(+e.target.value) });
    const play = el('button', { 'data-testid': 'play', onclick: () => { if (!view) return; view.playing ? view.pause() : view.play(); play.textContent = view.playing ? 'pause' : 'play'; } }, 'play');
    const speed = el('select', { 'data-testid': 'speed', onchange: (e) => { if (view) view.speed = +e.target.value; } },
      [0.25, 0.5, 1, 2, 4].map((s) => el('option', { value: s, selected: s === 1 }, `${s}\u00d7`)));
    const cameraSelect = el('select', { 'data-testid': 'camera', onchange: (e) => view && view.useCamera(e.target.value) }, el('option', { value: '' }, 'free orbit'));
    // Dragging the view leaves the camera chosen: the select says so.
    if (view) view.controls.addEventListener('start', () => { cameraSelect.value = ''; });
    const controls = el('div', { class: 'player' }, play, scrub, timeText, el('label', {}, 'speed ', speed), el('label', {}, 'camera ', cameraSelect));
    // The timeline: steps as bands, notable events as marks; clicking jumps there.
    const W = 900, H = 46;
    const tx = S.scale(0, duration || 1, 8, W - 8);
    const timeline = svg('svg', { viewBox: `0 0 ${W} ${H}`, class: 'timeline', 'data-testid': 'timeline' });
    steps.forEach((s, i) => {
      if (typeof s.start !== 'number') return;  // a step the run never began
      const end = typeof s.end === 'number' ? s.end : duration;
      timeline.append(svg('rect', { x: tx(s.start), y: 4, width: Math.max(1, tx(end) - tx(s.start)), height: 16,
        class: `step s${i % 6}`, onclick: () => seek(s.start) }, svg('title', {}, `${s.label}: ${S.num(s.duration, 's')}`)));
    });
    S.notableEvents(events).forEach((e) => timeline.append(svg('circle', { cx: tx(e.t), cy: 32, r: 5, class: `event ${e.kind}`, onclick: () => jump(e) },
      svg('title', {}, `${e.kind} at ${S.time(e.t)} s`))));
    // Where the run came closest (or went deepest): a mark that jumps there and frames the pair.
    if (mc && typeof mc.t === 'number')
      timeline.append(svg('path', { d: `M${tx(mc.t)},24 l6,8 l-6,8 l-6,-8 z`, class: `min-clearance${mc.distance < 0 ? ' penetration' : ''}`,
        'data-testid': 'min-clearance-mark',
        onclick: () => { seek(mc.t); view && view.frameObjects([mc.a.split('.')[0], mc.b.split('.')[0]]); } },
      svg('title', {}, `${mc.distance < 0 ? 'deepest penetration' : `minimum clearance${mc.certified ? ' (certified)' : ''}`} `
        + `${S.num(Math.abs(mc.distance), 'm')}: ${mc.a} and ${mc.b} at ${S.time(mc.t)} s`)));
    const playhead = svg('line', { y1: 0, y2: H, class: 'cursor' });
    timeline.append(playhead);
    const eventList = el('table', { class: 'events', 'data-testid': 'events' }, el('thead', {}, el('tr', {}, el('th', {}, 't (s)'), el('th', {}, 'event'), el('th', {}, 'details'))),
      el('tbody', {}, events.map((e, i) => el('tr', { 'data-event': i, class: e.kind, onclick: () => jump(e) }, el('td', { class: 'num' }, S.time(e.t)), el('td', {}, e.kind),
        el('td', {}, Object.entries(e).filter(([k]) => k !== 't' && k !== 'kind')
          .map(([k, x]) => (k === 'step' && typeof x === 'number' ? `step ${x + 1}` : `${k}: ${typeof x === 'object' ? JSON.stringify(x) : x}`)).join(', '))))));
    // Cycle time per step.
    const maxDur = Math.max(...steps.map((s) => s.duration || 0), 1e-9);
    const breakdown = el('table', { class: 'breakdown', 'data-testid': 'breakdown' }, steps.map((s) => el('tr', { onclick: () => typeof s.start === 'number' && seek(s.start) },
      el('td', {}, s.label), el('td', {}, s.device), el('td', { class: 'num' }, s.duration === null ? 'not finished' : S.num(s.duration, 's')),
      el('td', { class: 'bar' }, el('span', { style: `width:${(100 * (s.duration || 0)) / maxDur}%` })))));
    // Joint position and velocity per device.
    const plots = [];
    const plotBox = el('div', { class: 'plots' });
    for (const [device, csv] of Object.entries(data.trajectories || {})) {
      const t = S.parseCsv(csv);
      const ti = t.columns.indexOf('t');
      const joints = t.columns.filter((c, i) => i !== ti && !c.startsWith('tool_'));
      const xs = t.rows.map((r) => r[ti]);
      const pos = joints.map((j) => ({ name: j, xs, ys: t.rows.map((r) => r[t.columns.indexOf(j)]) }));
      const vel = pos.map((s) => ({ name: s.name, xs, ys: s.ys.map((y, k) => (k === 0 ? 0 : (y - s.ys[k - 1]) / ((xs[k] - xs[k - 1]) || Infinity))) }));
      const p1 = linePlot(pos, { xLabel: 't (s)', yLabel: 'position (deg | m)', onClick: seek });
      const p2 = linePlot(vel, { xLabel: 't (s)', yLabel: 'velocity (deg/s | m/s)', onClick: seek });
      plots.push(p1, p2);
      plotBox.append(el('figure', { 'data-device': device }, el('figcaption', {}, `${device}: joint positions`), p1.svg),
                     el('figure', {}, el('figcaption', {}, `${device}: joint velocities`), p2.svg));
    }
    // A campaign: its jobs per device (a Gantt chart), the queue and each device's utilization.
    const campaign = campaignSection(sum.campaign, data.jobs, duration, (t) => seek(t), (names) => view && view.frameObjects(names), plots);
    function onTime(t) {
      timeText.textContent = `${t.toFixed(2)} s`;
      if (campaign) campaign.cursor(t);
      if (+scrub.value !== t) scrub.value = t;
      playhead.setAttribute('x1', tx(t));
      playhead.setAttribute('x2', tx(t));
      for (const p of plots) p.cursor(t);
      if (view && !view.playing) play.textContent = 'play';
    }
    function seek(t) { if (view) view.setTime(t); else onTime(t); }
    // An event: its time, and the objects it names framed (a collision's pair, a grasp's drum).
    function jump(e) {
      seek(e.t);
      const named = ['a', 'b', 'object', 'device', 'on'].map((k) => e[k]).filter((x) => typeof x === 'string').map((x) => x.split('.')[0]);
      if (view && e.kind !== 'step_start' && e.kind !== 'step_end' && named.length) view.frameObjects(named);
    }
    v.panel.append(controls, timeline);
    app.append(el('main', { class: 'run' }, v.panel,
      el('section', { class: 'side' }, el('h2', {}, 'Cycle time by step'), breakdown, el('h2', {}, 'Events'), el('div', { class: 'scroll' }, eventList))),
      ...(campaign ? [campaign.section] : []), el('section', { class: 'wide' }, el('h2', {}, 'Joints'), plotBox));  // (a null appended read "null")
    if (view) view.ready.then(() => {
      for (const c of view.cameras) cameraSelect.append(el('option', { value: c.name }, c.name === 'run' ? "the run's camera" : c.name));
      onTime(0);
    });
    return { kind: 'run', view, seek, jump, events, duration };
  }

  /** A campaign run's section (campaign-format.md): its figures, a Gantt chart of the jobs per
   *  device (a bar per job from start to end, its wait from ready to start shaded under it,
   *  failures red, jobs never started in a row of their own; a click jumps there and frames the
   *  job's object), the queue's length and each device's utilization over time, and a button to
   *  the final state. Null for a scenario's run. */
  function campaignSection(c, jobsCsv, duration, seek, frame, plots) {
    if (!c || typeof jobsCsv !== 'string') return null;
    const jobs = S.campaignJobs(jobsCsv);
    const devices = Object.keys(c.devices || {});
    const end = Math.max(duration, ...jobs.map((j) => (typeof j.end === 'number' ? j.end : 0)));
    const rows = devices.concat(jobs.some((j) => j.status === 'not_started') ? ['not started'] : []);
    const W = 900, RH = 24, L = 120, H = rows.length * RH + 22;
    const gx = S.scale(0, end || 1, L, W - 8);
    const gantt = svg('svg', { viewBox: `0 0 ${W} ${H}`, class: 'gantt', 'data-testid': 'gantt' });
    rows.forEach((d, r) => gantt.append(svg('text', { x: L - 6, y: r * RH + 16, 'text-anchor': 'end' }, d)));
    for (const t of gx.ticks(8)) {
      gantt.append(svg('line', { x1: gx(t), x2: gx(t), y1: 0, y2: rows.length * RH, class: 'gridline' }));
      gantt.append(svg('text', { x: gx(t), y: H - 6, 'text-anchor': 'middle' }, S.num(t)));
    }
    const templates = [...new Set(jobs.map((j) => j.job))];
    jobs.forEach((j, i) => {
      const y = (j.status === 'not_started' ? rows.length - 1 : devices.indexOf(j.device)) * RH;
      if (y < 0) return;
      const said = `${j.job} ${j.object}${j.place ? ` to ${j.place}` : ''}: ${j.status.replace('_', ' ')}`
        + (typeof j.start === 'number' ? `, ${S.time(j.start)}–${S.time(j.end)} s, waited ${S.num(j.wait, 's')}` : '')
        + (j.message ? ` (${j.message})` : '');
      const go = () => { seek(typeof j.start === 'number' ? j.start : j.ready || 0); frame([j.object]); };
      if (typeof j.start !== 'number') {
        gantt.append(svg('rect', { x: gx(j.ready || 0), y: y + 4, width: 3, height: 14, class: 'job not-started', 'data-job': i, onclick: go },
          svg('title', {}, said)));
        return;
      }
      if (typeof j.ready === 'number' && j.start > j.ready + 1e-9)
        gantt.append(svg('rect', { x: gx(j.ready), y: y + 19, width: Math.max(1, gx(j.start) - gx(j.ready)), height: 4, class: 'wait' },
          svg('title', {}, `${j.object} waited ${S.num(j.wait, 's')}`)));
      gantt.append(svg('rect', { x: gx(j.start), y: y + 4, width: Math.max(1, gx(typeof j.end === 'number' ? j.end : end) - gx(j.start)), height: 14,
        class: `job ${j.status === 'failed' ? 'failed' : `s${templates.indexOf(j.job) % 6}`}`, 'data-job': i, onclick: go }, svg('title', {}, said)));
    });
    const playhead = svg('line', { y1: 0, y2: rows.length * RH, class: 'cursor' });
    gantt.append(playhead);
    const queue = linePlot([{ name: 'queue', ...S.queueSeries(jobs, end) }], { xLabel: 't (s)', yLabel: 'jobs waiting', onClick: seek });
    // To the last job's end, as the makespan runs (the run may go on while what was set down settles).
    const lastEnd = Math.max(0, ...jobs.map((j) => (typeof j.end === 'number' ? j.end : 0)));
    const use = linePlot(devices.map((d) => ({ name: d, ...S.utilizationSeries(jobs, d, lastEnd || end) })),
      { xLabel: 't (s)', yLabel: 'utilization so far', onClick: seek });
    plots.push(queue, use);
    const busy = devices.map((d) => `${d} ${S.num(100 * c.devices[d].utilization)} % busy`).join(', ');
    const section = el('section', { class: 'wide campaign', 'data-testid': 'campaign' }, el('h2', {}, 'Campaign'),
      el('p', { 'data-testid': 'campaign-figures' }, `${c.jobs.done} done, ${c.jobs.failed} failed, ${c.jobs.not_started} not started; `
        + `makespan ${S.num(c.makespan, 's')}, throughput ${S.num(c.throughput)} jobs/h, wait mean ${S.num(c.wait.mean, 's')} `
        + `(max ${S.num(c.wait.max, 's')}), queue at most ${c.queue_max}; ${busy}. `,
        el('button', { 'data-testid': 'final-state', onclick: () => seek(duration) }, 'final state')),
      el('figure', {}, el('figcaption', {}, 'Jobs per device: a bar per job from its start to its end, its wait from ready to start '
        + 'shaded under it, failures red (click one: the view jumps there)'), gantt),
      el('div', { class: 'plots' }, el('figure', {}, el('figcaption', {}, 'Queue: jobs ready and waiting'), queue.svg),
        el('figure', {}, el('figcaption', {}, 'Utilization so far: time busy over time since the first job was ready'), use.svg)));
    return { section, cursor: (t) => { playhead.setAttribute('x1', gx(t)); playhead.setAttribute('x2', gx(t)); } };
  }

  function sweepPage(data, app) {
    const res = data.results;
    const rows = S.sweepRows(res).map((r) => Object.assign(r, { id: String(r.variant), subjects: [] }));
    const params = (res.parameters || []).map((p) => p.name), metrics = res.metrics || [];
    const plotted = [...metrics, ...(res.simulated ? ['cycle_time', 'collisions'] : [])];
    const counts = {};
    for (const r of rows) counts[r.status] = (counts[r.status] || 0) + 1;
    app.append(header(`sscs sweep \u2014 ${res.sweep}`, el('span', {}, `${rows.length} variants`),
      Object.entries(counts).map(([k, n]) => chip(k, `${n} ${k}`))));
    const unitOf = Object.fromEntries((res.parameters || []).map((p) => [p.name, p.unit || '']));
    const columns = [
      { key: 'variant', label: '#', numeric: true },
      { key: 'status', label: 'Status', render: (r) => chip(r.status) },
      ...params.map((p) => ({ key: p, label: unitOf[p] ? `${p} (${unitOf[p]})` : p, numeric: true, render: (r) => (typeof r[p] === 'string' ? r[p] : S.num(r[p])) })),
      ...metrics.map((m) => ({ key: m, label: m, numeric: true, render: (r) => S.num(r[m]) })),
      ...(res.simulated ? [{ key: 'cycle_time', label: 'cycle time (s)', numeric: true, render: (r) => S.num(r.cycle_time) },
                           { key: 'collisions', label: 'collisions', numeric: true }] : []),
      { key: 'failed', label: 'failed', numeric: true },
      { key: 'folder', label: 'Variant', render: (r) => {
        // Only a relative file path is a link (results.json is an artifact anyone can edit).
        // sscs wrote a link for each folder it found in the sweep; none for any other.
        const href = Object.prototype.hasOwnProperty.call(data.links || {}, r.folder) ? S.relativeLink(data.links[r.folder]) : null;
        return href ? el('a', { href }, nameEl(r.folder)) : nameEl(r.folder);
      } },
      { key: 'message', label: 'Message' },
    ];
    let chosen = null;
    const table = new Table(columns, rows, { rowClass: (r) => r.status, onSelect: (r) => { chosen = r; draw(); }, onFilter: () => draw() });
    const filters = table.controls([['status', 'Status']], 'search variants, messages');
    const xSel = el('select', { 'data-testid': 'plot-x', onchange: () => draw() }, [...params, ...plotted].map((c) => el('option', { value: c }, c)));
    const ySel = el('select', { 'data-testid': 'plot-y', onchange: () => draw() }, [...plotted, ...params].map((c) => el('option', { value: c }, c)));
    const plotBox = el('div', { class: 'scatter', 'data-testid': 'scatter' });
    function draw() {
      const xk = xSel.value, yk = ySel.value;
      const W = 640, H = 340, m = { l: 64, r: 16, t: 12, b: 40 };
      // A column of words (the vault or scenario files a sweep compares) is an axis of categories.
      // The rows the table's filters keep; failing points first, so a passing one is never hidden under one.
      const kept = table.visible().slice().sort((a, b) => (a.status === 'pass') - (b.status === 'pass'));
      const xa = S.axis(rows, xk), ya = S.axis(rows, yk);
      const x = S.axisScale(xa, rows, m.l, W - m.r), y = S.axisScale(ya, rows, H - m.b, m.t);
      const g = svg('svg', { viewBox: `0 0 ${W} ${H}`, class: 'plot', width: W, height: H });
      axes(g, x, y, W, H, m, xk, yk);
      const shown = (v) => (typeof v === 'number' ? S.num(v) : String(v));
      for (const r of kept) {
        const xv = xa.get(r), yv = ya.get(r);
        if (xv === undefined || yv === undefined) continue;
        g.append(svg('circle', { cx: x(xv), cy: y(yv), r: r === chosen ? 7 : 4.5, fill: STATUS_COLOUR[r.status] || '#555', class: r === chosen ? 'chosen' : '',
          'data-variant': r.variant, onclick: () => table.select(r) }, svg('title', {}, `${r.folder}: ${xk} ${shown(r[xk])}, ${yk} ${shown(r[yk])} (${r.status})`)));
      }
      Object.keys(counts).forEach((k, i) => {
        g.append(svg('circle', { cx: W - m.r - 90, cy: m.t + 8 + i * 14, r: 4.5, fill: STATUS_COLOUR[k] || '#555' }));
        g.append(svg('text', { x: W - m.r - 80, y: m.t + 12 + i * 14 }, k));
      });
      plotBox.replaceChildren(g);
    }
    draw();
    app.append(el('main', { class: 'sweep' }, el('section', { class: 'plot-panel' }, el('div', { class: 'filters' }, el('label', {}, 'x ', xSel), el('label', {}, 'y ', ySel)), plotBox),
      el('section', { class: 'table-panel' }, filters, el('div', { class: 'scroll' }, table.element))));
    return { kind: 'sweep', table, rows, draw };
  }

  function start() {
    const data = JSON.parse(document.getElementById('sscs-data').textContent);
    const app = document.getElementById('app');
    app.replaceChildren();
    document.title = data.title || 'sscs report';
    const page = data.kind === 'check' ? checkPage(data, app) : data.kind === 'run' ? runPage(data, app) : sweepPage(data, app);
    app.append(el('footer', {}, `made by ${data.generator || 'sscs'}${data.source ? ` from ${data.source}` : ''}; opens from disk, nothing fetched`));
    root.sscsReport = Object.assign(page, { data, ready: page.view ? page.view.ready.then(() => true) : Promise.resolve(true) });
  }

  /** sscs serve: builds the page again from the report now in the document (its data and model
   *  elements replaced), keeping the 3D view (canvas, camera, switches) of a check page. */
  root.sscsRebuild = ({ keepModel = false } = {}) => {
    const old = root.sscsReport;
    spare = old && old.kind === 'check' && old.view && !old.view.disposed ? old.view : null;
    spareKeepsModel = !!spare && keepModel;
    if (old && old.view && !spare && !old.view.disposed) old.view.dispose();  // (a run's page: a new view)
    // The table as the user left it: its sort and the row selected (by its id), when it is still there.
    const sort = old && old.table ? old.table.sort : null;
    const was = old && old.table && old.table.selected;
    const same = (r) => was && r.constraint === was.constraint && (r.subjects || []).join('|') === (was.subjects || []).join('|');
    start();
    const page = root.sscsReport;
    if (page.table && sort && sort.key) {
      page.table.sort = { key: sort.key, dir: -sort.dir };
      page.table.sortBy(sort.key);  // (flips it back, marking the header)
    }
    if (page.table && was) {  // kept selected, without moving the camera to it again
      page.table.selected = page.table.rows.find(same) || null;
      page.table.draw();
      const row = page.table.selected;
      if (row && page.view) page.view.ready.then((v) => { v.showClosest(row.closest && row.subjects[0], row.closest); page.drawReach(v, row); });
    }
    return page.ready;
  };

  if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start); else start();
})(typeof globalThis !== 'undefined' ? globalThis : this);
