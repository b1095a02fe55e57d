-- Neovim smoke test (run by lsp/tests/neovim_smoke.rs): loads editors/neovim/gutta-lsp.lua
-- as a user would, then, once the edited .lad file's diagnostics arrive, asks for a hover
-- at the line and column the test names, writes what it got as JSON to a file and quits.
-- Environment: GUTTA_NVIM_CONFIG (the config), GUTTA_NVIM_OUT (the answer file),
-- GUTTA_HOVER_LINE and GUTTA_HOVER_COLUMN (0-based), GUTTA_NVIM_TIMEOUT_MS.

dofile(os.getenv('GUTTA_NVIM_CONFIG'))

local out_path = os.getenv('GUTTA_NVIM_OUT')
local hover_line = tonumber(os.getenv('GUTTA_HOVER_LINE'))
local hover_column = tonumber(os.getenv('GUTTA_HOVER_COLUMN'))
local timeout_ms = tonumber(os.getenv('GUTTA_NVIM_TIMEOUT_MS') or '20000')

local function finish(result)
  local file = io.open(out_path, 'w')
  file:write(vim.fn.json_encode(result))
  file:close()
  vim.cmd('qall!')
end

local function hover_text(bufnr)
  for _, client in pairs(vim.lsp.buf_get_clients(bufnr)) do
    local caps = client.server_capabilities or {}
    if not caps.hoverProvider then
      return 'error: the server does not offer hoverProvider'
    end
  end
  local params = {
    textDocument = { uri = vim.uri_from_bufnr(bufnr) },
    position = { line = hover_line, character = hover_column },
  }
  local answers = vim.lsp.buf_request_sync(bufnr, 'textDocument/hover', params, 5000)
  for _, answer in pairs(answers or {}) do
    local err = answer.err or answer.error -- `err` up to Neovim 0.10
    if err then
      return 'error: ' .. vim.fn.json_encode(err)
    end
    local contents = answer.result and answer.result.contents
    if type(contents) == 'table' then
      if contents.value then
        return contents.value
      end
      return vim.fn.json_encode(contents)
    elseif contents then
      return contents
    end
  end
  return vim.NIL
end

local function poll(bufnr, started)
  local diagnostics = vim.diagnostic.get(bufnr)
  if #diagnostics > 0 then
    local seen = {}
    for _, d in ipairs(diagnostics) do
      table.insert(seen, { code = d.code, line = d.lnum, message = d.message, source = d.source })
    end
    finish({
      filetype = vim.bo[bufnr].filetype,
      clients = #vim.lsp.get_active_clients(),
      diagnostics = seen,
      hover = hover_text(bufnr),
    })
  elseif vim.loop.now() - started > timeout_ms then
    finish({
      filetype = vim.bo[bufnr].filetype,
      clients = #vim.lsp.get_active_clients(),
      diagnostics = {},
      hover = vim.NIL,
      timeout = true,
    })
  else
    vim.defer_fn(function()
      poll(bufnr, started)
    end, 50)
  end
end

vim.api.nvim_create_autocmd('VimEnter', {
  callback = function()
    local bufnr = vim.api.nvim_get_current_buf()
    vim.loop.update_time()
    poll(bufnr, vim.loop.now())
  end,
})
