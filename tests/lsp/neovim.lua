-- Neovim's own LSP client (Debian's neovim 0.7), started by the set-up docs/editing.md gives,
-- talking to `sscs lsp` on a copy of the reference store: a typo typed is underlined with its
-- did-you-mean before any save; hover on a type, definition of a row, completion after
-- `at: EndWall.` and the document's symbols. Run by neovim.sh.
local vault = os.getenv('VAULT')

local function fail(message)
  io.stderr:write('neovim.lua: ' .. message .. '\n')
  vim.cmd('cquit 1')
end

local publishes = 0
local default_publish = vim.lsp.handlers['textDocument/publishDiagnostics']
vim.lsp.handlers['textDocument/publishDiagnostics'] = function(err, result, ctx, config)
  publishes = publishes + 1
  return default_publish(err, result, ctx, config)
end

vim.cmd('edit ' .. vim.fn.fnameescape(vault))  -- the set-up of docs/editing.md (init.lua) starts the client on FileType yaml
local id
vim.wait(10000, function()
  for _, c in ipairs(vim.lsp.get_active_clients()) do
    if c.name == 'sscs' then id = c.id end
  end
  return id ~= nil
end, 50)
if not id then fail('the set-up of docs/editing.md started no sscs client (filetype ' .. vim.bo.filetype .. ')') end
if not vim.wait(30000, function() return publishes > 0 end, 50) then fail('no diagnostics published for the opened store') end
local function errors()
  return vim.diagnostic.get(0, { severity = vim.diagnostic.severity.ERROR })
end
if #errors() > 0 then fail('the store has errors: ' .. vim.inspect(errors())) end

local lines = vim.api.nvim_buf_get_lines(0, 0, -1, false)
local function line_of(needle)
  for i, l in ipairs(lines) do
    if l:find(needle, 1, true) then return i - 1, l end
  end
  fail('no line holds ' .. needle)
end

-- A typo typed (the file on disk keeps `length`).
local hall, hall_text = line_of('name: Hall, length: 30 m')
local col = hall_text:find('length', 1, true) - 1
vim.api.nvim_buf_set_text(0, hall, col, hall, col + 6, { 'lenght' })
local typo
vim.wait(30000, function()
  for _, d in ipairs(errors()) do
    if d.message:find("did you mean 'length'", 1, true) then typo = d return true end
  end
  return false
end, 50)
if not typo then fail('no did-you-mean for the typo: ' .. vim.inspect(vim.diagnostic.get(0))) end
if typo.lnum ~= hall or typo.col ~= col or typo.end_col ~= col + 6 then fail('the typo is underlined at ' .. vim.inspect(typo)) end
vim.api.nvim_buf_set_text(0, hall, col, hall, col + 6, { 'length' })
if not vim.wait(30000, function() return #errors() == 0 end, 50) then fail('the fixed typo still shows: ' .. vim.inspect(errors())) end

local uri = vim.uri_from_bufnr(0)
local function ask(method, line, character)
  local answers = vim.lsp.buf_request_sync(0, method, { textDocument = { uri = uri }, position = { line = line, character = character } }, 10000)
  local answer = answers and answers[id]
  if not answer or answer.err then fail(method .. ' failed: ' .. vim.inspect(answers)) end
  return answer.result
end

local rack = line_of('- type: drum_rack')
local hover = ask('textDocument/hover', rack, 12)
if not (hover and hover.contents.value:find('| levels | integer |', 1, true)) then fail('hover on drum_rack: ' .. vim.inspect(hover)) end

local array = line_of('array: {name: "Row_{i}"')
local use, use_text = line_of('Row_1.level_capacity')
local definition = ask('textDocument/definition', use, use_text:find('Row_1.level_capacity', 1, true))
if not (definition and definition.uri == uri and definition.range.start.line == array) then fail('definition of Row_1: ' .. vim.inspect(definition)) end

local door, door_text = line_of('at: EndWall.opening_1')
local dot = door_text:find('EndWall.', 1, true) + #'EndWall.' - 1
vim.api.nvim_buf_set_text(0, door, dot, door, dot + #'opening_1', { '' })
local completion = ask('textDocument/completion', door, dot)
local labels = {}
for _, item in ipairs(completion.items or completion) do labels[item.label] = true end
if not (labels['opening_1'] and labels['top']) then fail('completion after EndWall.: ' .. vim.inspect(vim.tbl_keys(labels))) end

local symbols = vim.lsp.buf_request_sync(0, 'textDocument/documentSymbol', { textDocument = { uri = uri } }, 10000)[id].result
local names = {}
for _, s in ipairs(symbols) do names[s.name] = true end
if not (names['Hall'] and names['Crane'] and names['nothing overlaps']) then fail('symbols: ' .. vim.inspect(vim.tbl_keys(names))) end

io.stdout:write('neovim.lua: diagnostics, hover, definition, completion and symbols through neovim ' .. tostring(vim.version().minor) .. '\n')
vim.lsp.stop_client(id)
vim.cmd('qall!')
