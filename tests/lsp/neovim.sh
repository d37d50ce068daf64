#!/usr/bin/env bash
# Neovim headless, its own LSP client started by the set-up docs/editing.md gives, against
# `sscs lsp` on a copy of the reference store (neovim.lua says what it checks).
# Usage: neovim.sh SSCS SOURCE_DIR
set -euo pipefail
sscs=$1 source=$2
if ! command -v nvim >/dev/null; then
  echo "neovim.sh: nvim is not installed (tools/setup.sh installs it): skipped"
  exit 77
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cp "$source/scenarios/drum-store/store.yaml" "$dir/store.yaml"
cp "$dir/store.yaml" "$dir/store.orig"
# The set-up docs/editing.md gives for Neovim, as written: its init.lua block (with `sscs` on PATH).
awk '/^\*\*Neovim\*\*/ { want = 1 } want && /^```lua/ { on = 1; next } on && /^```/ { exit } on { print }' \
  "$source/docs/editing.md" > "$dir/init.lua"
grep -q "vim.lsp.start_client" "$dir/init.lua" || { echo "neovim.sh: no Neovim set-up found in docs/editing.md"; exit 1; }
mkdir -p "$dir/bin"
ln -s "$(cd "$(dirname "$sscs")" && pwd)/$(basename "$sscs")" "$dir/bin/sscs"
PATH=$dir/bin:$PATH VAULT=$dir/store.yaml HOME=$dir XDG_CONFIG_HOME=$dir XDG_DATA_HOME=$dir XDG_STATE_HOME=$dir \
  timeout 120 nvim --headless -n -u "$dir/init.lua" -c "luafile $source/tests/lsp/neovim.lua"
cmp "$dir/store.yaml" "$dir/store.orig"  # never saved: the server read the buffer, not the file
