// `sscs lsp` driven by a scripted editor: vscode-jsonrpc, the JSON-RPC library VS Code's own
// language client is built on, over the server's stdin and stdout. A copy of the reference store
// is opened; a typo typed (never saved) is underlined with its did-you-mean; a rack moved into a
// wall gets the failed constraint at its line; hover on a type lists its attributes; definition of
// a row jumps to its line; completion after `at: EndWall.` lists the wall's frames; a 50 MB buffer
// does not stop the server answering; shutdown and exit end it with status 0.
// Usage: SSCS=path/to/sscs SSCS_SOURCE=source dir node --test lsp.test.mjs
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { mkdtempSync, copyFileSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';
import rpc from 'vscode-jsonrpc/node.js';

const sscs = process.env.SSCS, source = process.env.SSCS_SOURCE;
assert.ok(sscs && source, 'SSCS and SSCS_SOURCE are set');
const dir = mkdtempSync(join(tmpdir(), 'sscs-lsp-'));
const vault = join(dir, 'store.yaml');
copyFileSync(join(source, 'scenarios/drum-store/store.yaml'), vault);
const text = readFileSync(vault, 'utf8');
const uri = pathToFileURL(vault).href;
let server, connection, version = 1;
const published = new Map();  // uri -> the last diagnostics
const waiting = [];

function diagnosticsWhere(want, predicate, ms = 20000) {
  return new Promise((resolve, reject) => {
    const check = () => {
      const d = published.get(want);
      if (d && predicate(d)) {
        resolve(d);
        return true;
      }
      return false;
    };
    if (check()) return;
    const timer = setTimeout(() => reject(new Error(`no such diagnostics for ${want}: ${JSON.stringify(published.get(want))}`)), ms);
    waiting.push(() => check() && (clearTimeout(timer), true));
  });
}

function edited(from, to) {
  assert.ok(text.includes(from), from);
  return text.replace(from, to);
}

function change(newText, file = uri) {
  published.delete(file);
  connection.sendNotification('textDocument/didChange', { textDocument: { uri: file, version: ++version }, contentChanges: [{ text: newText }] });
}

const lineOf = (needle) => text.split('\n').findIndex((l) => l.includes(needle));

before(async () => {
  server = spawn(sscs, ['lsp'], { cwd: dir, stdio: ['pipe', 'pipe', 'inherit'] });
  connection = rpc.createMessageConnection(new rpc.StreamMessageReader(server.stdout), new rpc.StreamMessageWriter(server.stdin));
  connection.onNotification('textDocument/publishDiagnostics', (p) => {
    published.set(p.uri, p.diagnostics);
    for (let i = waiting.length - 1; i >= 0; --i) if (waiting[i]()) waiting.splice(i, 1);
  });
  connection.listen();
  const init = await connection.sendRequest('initialize', { processId: process.pid, rootUri: pathToFileURL(dir).href, capabilities: {} });
  assert.equal(init.capabilities.positionEncoding, 'utf-16');
  assert.equal(init.capabilities.textDocumentSync.change, 2);
  connection.sendNotification('initialized', {});
  connection.sendNotification('textDocument/didOpen', { textDocument: { uri, languageId: 'yaml', version, text } });
});

after(() => {
  connection?.dispose();
  server?.kill();
  rmSync(dir, { recursive: true, force: true });
});

test('the reference store opens without an error', async () => {
  const d = await diagnosticsWhere(uri, () => true);
  assert.deepEqual(d.filter((x) => x.severity === 1), [], JSON.stringify(d));
});

test('a typo typed, not saved, is underlined with its did-you-mean', async () => {
  change(edited('name: Hall, length: 30 m', 'name: Hall, lenght: 30 m'));
  const d = await diagnosticsWhere(uri, (d) => d.length > 0);
  const typo = d.find((x) => x.message.includes("'lenght'"));
  assert.ok(typo, JSON.stringify(d));
  assert.match(typo.message, /did you mean 'length'/);
  const line = lineOf('name: Hall, length: 30 m');
  const column = text.split('\n')[line].indexOf('length');
  assert.deepEqual(typo.range, { start: { line, character: column }, end: { line, character: column + 6 } });
  assert.equal(readFileSync(vault, 'utf8'), text, 'the server never writes the file');
  change(text);
  await diagnosticsWhere(uri, (d) => d.every((x) => x.severity !== 1));
});

test('a rack moved into the front wall fails its constraint at the constraint\'s line', async () => {
  change(edited('name: GoodsRack, parent: Hall, location: [9, 2.0, 0]', 'name: GoodsRack, parent: Hall, location: [9, 0.65, 0]'));
  const d = await diagnosticsWhere(uri, (d) => d.some((x) => x.severity === 1));
  const overlap = d.find((x) => x.message.includes('nothing overlaps'));
  assert.ok(overlap, JSON.stringify(d));
  assert.match(overlap.message, /GoodsRack/);
  assert.match(overlap.message, /FrontWall/);
  assert.match(overlap.message, /margin -/);
  assert.equal(overlap.range.start.line, lineOf('name: nothing overlaps'));
  change(text);
  await diagnosticsWhere(uri, (d) => d.every((x) => x.severity !== 1));
});

test('hover on a type lists its attributes with units and defaults', async () => {
  const line = lineOf('- type: drum_rack');
  const h = await connection.sendRequest('textDocument/hover', { textDocument: { uri }, position: { line, character: 12 } });
  assert.match(h.contents.value, /\*\*drum\\_rack\*\*/);
  assert.match(h.contents.value, /\| levels \| integer \|/);
  assert.match(h.contents.value, /\| level\\_height \| length \| m \| 1\.27 \| 0\.3 to 5 m \|/);
});

test('hover on an object shows its type, world position and bounding box', async () => {
  const line = lineOf('rollup_door, name: TruckDoor, at: EndWall.opening_1');
  const character = text.split('\n')[line].indexOf('EndWall.') + 2;
  const h = await connection.sendRequest('textDocument/hover', { textDocument: { uri }, position: { line, character } });
  assert.match(h.contents.value, /\*\*EndWall\*\*: `wall`/);
  assert.match(h.contents.value, /world position: \[-0\.3, 12, 0\] m/);
  assert.match(h.contents.value, /bounding box: /);
});

test('definition of a row jumps to the array that makes it', async () => {
  const line = lineOf('Row_1.level_capacity');
  const character = text.split('\n')[line].indexOf('Row_1.level_capacity') + 2;
  const loc = await connection.sendRequest('textDocument/definition', { textDocument: { uri }, position: { line, character } });
  assert.equal(loc.uri, uri);
  assert.equal(loc.range.start.line, lineOf('array: {name: "Row_{i}"'));  // the array's name pattern
});

test('completion after `at: EndWall.` lists the wall\'s frames', async () => {
  const typed = edited('at: EndWall.opening_1}', 'at: EndWall.}');
  change(typed);
  const line = lineOf('at: EndWall.opening_1');
  const character = text.split('\n')[line].indexOf('EndWall.') + 'EndWall.'.length;
  const c = await connection.sendRequest('textDocument/completion', { textDocument: { uri }, position: { line, character } });
  const labels = c.items.map((i) => i.label);
  for (const frame of ['opening_1', 'origin', 'top']) assert.ok(labels.includes(frame), labels.join(' '));
  assert.deepEqual(c.items[0].textEdit.range, { start: { line, character }, end: { line, character } });
  change(text);
});

test('an edit made while a long check runs stops that check: the new text is checked at once', async () => {
  // An arm reaching over a screen for N points behind it: each reached only in collision, after
  // the search's every approach and turn (a fifth of a second each).
  const screen = (n) => ['sscs: 1', 'vault: Screen', 'objects:',
    '  - {type: room, name: Room1, length: 10 m, width: 8 m, height: 5 m}',
    '  - {type: arm6, name: Arm, parent: Room1, location: [3, 4, 0]}',
    '  - {type: wall, name: Screen, parent: Room1, location: [4.0, 2, 0], orientation: [0, 0, 90], length: 4 m, thickness: 0.1 m, height: 3 m}',
    'constraints:',
    `  - {name: over the screen, reach: {device: Arm, targets: [${Array.from({ length: n }, (_, i) =>
      `{xyz: [4.25, ${(3.4 + (1.2 * i) / Math.max(1, n - 1)).toFixed(4)}, ${(0.6 + 0.04 * (i % 10)).toFixed(2)}]}`).join(', ')}]}}`, ''].join('\n');
  const file = pathToFileURL(join(dir, 'screen.yaml')).href;
  writeFileSync(join(dir, 'screen.yaml'), screen(1));
  connection.sendNotification('textDocument/didOpen', { textDocument: { uri: file, languageId: 'yaml', version: ++version, text: screen(1) } });
  await diagnosticsWhere(file, (d) => d.length === 1);
  change(screen(400), file);  // a check of a minute and more
  await new Promise((r) => setTimeout(r, 1500));
  const start = Date.now();
  // The cell with two failing bounds and no reach: checked in no time (what is measured is how
  // soon the long check stops).
  change(screen(0).replace(/  - \{name: over the screen.*\n/, '  - {name: low, bound: [Screen.height, LT, 1 m]}\n  - {name: short, bound: [Screen.length, LT, 1 m]}\n'), file);
  const d = await diagnosticsWhere(file, (d) => d.length === 2, 30000);
  const ms = Date.now() - start;
  assert.ok(d.every((x) => /failed (low|short)/.test(x.message)), d.map((x) => x.message).join('\n'));
  assert.ok(ms < 10000, `the new text's diagnostics after ${ms} ms: the long check was waited for`);
  console.log(`lsp: an edit made during a long check, its diagnostics after ${ms} ms`);
  connection.sendNotification('textDocument/didClose', { textDocument: { uri: file } });
});

test('a 50 MB buffer does not stop the server answering', async () => {
  const big = pathToFileURL(join(dir, 'big.yaml')).href;
  const lines = ['sscs: 1', 'vault: Big', 'objects:'];
  const row = '  - {type: drum, name: D_NAME, location: [0, 0, 0]}  # ' + 'x'.repeat(120);
  for (let i = 0, size = 0; size < 50e6; ++i) {
    lines.push(row.replace('NAME', i));
    size += lines[lines.length - 1].length + 1;
  }
  const bigText = lines.join('\n') + '\n';
  assert.ok(bigText.length >= 50e6);
  connection.sendNotification('textDocument/didOpen', { textDocument: { uri: big, languageId: 'yaml', version: 1, text: bigText } });
  const start = Date.now();
  const symbols = await connection.sendRequest('textDocument/documentSymbol', { textDocument: { uri } });
  const ms = Date.now() - start;
  assert.ok(symbols.some((s) => s.name === 'Hall'), JSON.stringify(symbols.slice(0, 3)));
  assert.ok(ms < 5000, `answered in ${ms} ms`);
  connection.sendNotification('textDocument/didClose', { textDocument: { uri: big } });
});

test('a message without Content-Length is refused and the next one answered', async () => {
  const errors = [];
  connection.onError?.((e) => errors.push(e));
  server.stdin.write('Content-Type: application/vscode-jsonrpc\r\n\r\n{"jsonrpc":"2.0","id":9999,"method":"shutdown"}');
  const symbols = await connection.sendRequest('textDocument/documentSymbol', { textDocument: { uri } });
  assert.ok(symbols.some((s) => s.name === 'Hall'), JSON.stringify(symbols.slice(0, 3)));
});

test('shutdown and exit end the server with status 0', async () => {
  await connection.sendRequest('shutdown');
  const code = new Promise((resolve) => server.on('exit', resolve));
  connection.sendNotification('exit');
  assert.equal(await code, 0);
});
