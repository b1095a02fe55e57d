" GUTTA PLC programs: buffer settings that match the layout gutta-lsp's formatter writes
" (docs/language.md, "Layout"). Comments are `//` to the end of the line; declarations,
" data rows and system entries are indented by two blanks, never by a tab; everything
" else starts in column 0. Formatting itself is the language server's (docs/editors.md).

if exists('b:did_ftplugin')
  finish
endif
let b:did_ftplugin = 1

setlocal commentstring=//\ %s
setlocal comments=://
setlocal expandtab shiftwidth=2 softtabstop=2 autoindent
" Code is never wrapped (no t); comments wrap at 'textwidth' (c), continue after Enter
" and o/O (r, o), are formatted by gq (q), and lose their leader when joined (j).
setlocal formatoptions-=t formatoptions+=croqlj

let b:undo_ftplugin = 'setlocal commentstring< comments< expandtab< shiftwidth<'
      \ . ' softtabstop< autoindent< formatoptions<'
