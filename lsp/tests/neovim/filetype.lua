-- Neovim filetype test (run by lsp/tests/neovim_filetype.rs): with editors/neovim on
-- 'runtimepath' (ftdetect, ftplugin, syntax) and editors/neovim/gutta-lsp.lua loaded as
-- a user would, it reads the options and syntax groups of the edited .lad file, comments
-- a line with `gcc` where Neovim has it (0.10 and newer), then formats two badly laid out
-- files through gutta-lsp: one with the version's formatting call, one with `gq` over
-- the whole buffer ('formatexpr'). Writes what it saw as JSON and quits.
-- Environment: GUTTA_NVIM_RUNTIME (editors/neovim), GUTTA_NVIM_CONFIG (gutta-lsp.lua),
-- GUTTA_NVIM_OUT (the answer file), GUTTA_NVIM_PROBES (JSON: [[line, column], ...],
-- 1-based), GUTTA_NVIM_FORMAT and GUTTA_NVIM_GQ (the two files to format),
-- GUTTA_NVIM_TIMEOUT_MS.

vim.opt.runtimepath:append(os.getenv('GUTTA_NVIM_RUNTIME'))
dofile(os.getenv('GUTTA_NVIM_CONFIG'))

local out_path = os.getenv('GUTTA_NVIM_OUT')
local probes = vim.fn.json_decode(os.getenv('GUTTA_NVIM_PROBES'))
local timeout_ms = tonumber(os.getenv('GUTTA_NVIM_TIMEOUT_MS') or '20000')
local report = {}

local function finish()
  local file = io.open(out_path, 'w')
  file:write(vim.fn.json_encode(report))
  file:close()
  vim.cmd('qall!')
end

local function lines(bufnr)
  return table.concat(vim.api.nvim_buf_get_lines(bufnr, 0, -1, false), '\n') .. '\n'
end

-- The clients serving bufnr (`get_clients` from Neovim 0.10 on, `buf_get_clients` before).
local function clients_of(bufnr)
  if vim.lsp.get_clients then
    return vim.lsp.get_clients({ bufnr = bufnr })
  end
  return vim.lsp.buf_get_clients(bufnr)
end

-- Calls `ready(bufnr)` once a client serving bufnr has finished `initialize`.
local function when_served(bufnr, started, ready)
  for _, client in pairs(clients_of(bufnr)) do
    if client.server_capabilities and client.initialized ~= false then
      return ready(bufnr)
    end
  end
  if vim.loop.now() - started > timeout_ms then
    report.timeout = vim.api.nvim_buf_get_name(bufnr)
    return finish()
  end
  vim.defer_fn(function()
    when_served(bufnr, started, ready)
  end, 50)
end

local function format_with_gq()
  vim.cmd('edit ' .. vim.fn.fnameescape(os.getenv('GUTTA_NVIM_GQ')))
  local bufnr = vim.api.nvim_get_current_buf()
  vim.loop.update_time()
  when_served(bufnr, vim.loop.now(), function()
    -- Neovim 0.8 and newer set 'formatexpr' when the server formats ranges;
    -- gutta-lsp.lua sets it on 0.7.
    report.formatexprOnAttach = vim.bo[bufnr].formatexpr
    vim.cmd('normal! gggqG')
    report.gq = lines(bufnr)
    finish()
  end)
end

local function format_with_call()
  vim.cmd('edit ' .. vim.fn.fnameescape(os.getenv('GUTTA_NVIM_FORMAT')))
  local bufnr = vim.api.nvim_get_current_buf()
  vim.loop.update_time()
  when_served(bufnr, vim.loop.now(), function()
    if vim.lsp.buf.format then -- Neovim 0.8 and newer
      report.formatCall = 'vim.lsp.buf.format'
      vim.lsp.buf.format({ bufnr = bufnr, timeout_ms = 5000 })
    else -- Neovim 0.7
      report.formatCall = 'vim.lsp.buf.formatting_sync'
      vim.lsp.buf.formatting_sync(nil, 5000)
    end
    report.formatted = lines(bufnr)
    format_with_gq()
  end)
end

vim.api.nvim_create_autocmd('VimEnter', {
  nested = true, -- the :edit below runs BufRead and FileType (filetype, gutta-lsp)
  callback = function()
    local bufnr = vim.api.nvim_get_current_buf()
    local bo = vim.bo[bufnr]
    report.filetype = bo.filetype
    report.syntax = vim.b[bufnr].current_syntax or vim.NIL
    report.commentstring = bo.commentstring
    report.comments = bo.comments
    report.formatoptions = bo.formatoptions
    report.expandtab = bo.expandtab
    report.shiftwidth = bo.shiftwidth
    report.softtabstop = bo.softtabstop
    report.groups = {}
    for _, probe in ipairs(probes) do
      local name = vim.fn.synIDattr(vim.fn.synID(probe[1], probe[2], 1), 'name')
      table.insert(report.groups, name)
    end
    -- `gc` (comment an operator's lines) is built in from Neovim 0.10 on.
    report.hasGc = vim.fn.has('nvim-0.10') == 1
    if report.hasGc then
      vim.api.nvim_win_set_cursor(0, { probes[1][1], 0 })
      vim.cmd('normal gcc')
      report.gcc = vim.api.nvim_get_current_line()
      vim.cmd('normal gcc')
      report.gccTwice = vim.api.nvim_get_current_line()
    else
      report.gcc = vim.NIL
    end
    vim.cmd('write')
    format_with_call()
  end,
})
