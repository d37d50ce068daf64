// Starts `sscs lsp` for the YAML files of the workspace. sscs answers only for sscs files (a
// `vault:`, `scenario:`, `campaign:` or `type:` at the top); yaml-language-server (the YAML
// extension this one depends on) validates them against sscs's JSON Schemas at the same time.
const vscode = require('vscode');
const { LanguageClient } = require('vscode-languageclient/node');

let client;

function activate(context) {
  const config = vscode.workspace.getConfiguration('sscs');
  const server = { command: config.get('path', 'sscs'), args: ['lsp', ...config.get('arguments', [])] };
  client = new LanguageClient('sscs', 'sscs', { run: server, debug: server }, {
    documentSelector: [{ scheme: 'file', language: 'yaml' }],
  });
  context.subscriptions.push({ dispose: () => client && client.stop() });
  return client.start();
}

function deactivate() {
  return client ? client.stop() : undefined;
}

module.exports = { activate, deactivate };
