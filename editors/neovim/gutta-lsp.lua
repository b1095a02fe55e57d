-- gutta-lsp for Neovim 0.7 and newer (docs/editors.md): `.lad` files get the filetype
-- `gutta`, and each buffer of that filetype is served by the `gutta-lsp` of its
-- project (the folder of the nearest gutta.toml above the file, else the file's folder).
-- Put this file in ~/.config/nvim/plugin/ or `dofile()` it from init.lua.
-- lsp/tests/neovim_smoke.rs runs Neovim with this very file.

vim.api.nvim_create_autocmd({ 'BufRead', 'BufNewFile' }, {
  pattern = '*.lad',
  callback = function(args)
    vim.bo[args.buf].filetype = 'gutta'
  end,
})

local clients = {} -- Neovim 0.7: one client per project root, started by hand

vim.api.nvim_create_autocmd('FileType', {
  pattern = 'gutta',
  callback = function(args)
    local file = vim.api.nvim_buf_get_name(args.buf)
    local folder = vim.fn.fnamemodify(file, ':p:h')
    local project = vim.fn.findfile('gutta.toml', folder .. ';')
    local root = project ~= '' and vim.fn.fnamemodify(project, ':p:h') or folder
    local config = { name = 'gutta-lsp', cmd = { 'gutta-lsp' }, root_dir = root }
    if vim.lsp.start then -- Neovim 0.8 and newer: reuses a running client of that root
      vim.lsp.start(config, { bufnr = args.buf })
    else
      clients[root] = clients[root] or vim.lsp.start_client(config)
      vim.lsp.buf_attach_client(args.buf, clients[root])
      -- `gq` through the server's range formatting, as 0.8 and newer set it on attach
      vim.bo[args.buf].formatexpr = 'v:lua.vim.lsp.formatexpr()'
    end
  end,
})
