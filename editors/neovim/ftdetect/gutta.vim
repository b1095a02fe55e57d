" GUTTA PLC programs (docs/editors.md, "Neovim"): `.lad` sources and Micro/WIN STL
" exports (`.awl`) get the filetype `gutta`, which ftplugin/gutta.vim and
" syntax/gutta.vim set up and gutta-lsp.lua serves. Neovim 0.7 and newer, and Vim.
" lsp/tests/neovim_filetype.rs runs Neovim with this folder on 'runtimepath'.
autocmd BufRead,BufNewFile *.lad,*.awl setfiletype gutta
