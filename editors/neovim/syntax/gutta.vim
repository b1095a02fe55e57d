" GUTTA PLC programs (.lad, .awl): colours without the language server. Block keywords,
" NETWORK, the mnemonics of the stdlib's instruction set (the list between the markers
" is generated: lsp/tests/neovim_filetype.rs checks it), comments, strings, numbers
" (16#FF, 2#1010, 1.5e3), direct addresses (I0.0, MW10, SM0.5, T37), #locals and
" symbols. gutta-lsp's semantic tokens, where the editor asks for them, refine these.
" Vim 8 and Neovim 0.7 and newer.

if exists('b:current_syntax')
  finish
endif

syn case ignore

" Symbols first: every later item that starts at the same place wins over them.
syn match guttaSymbol /\%([[:alnum:]_#.]\)\@<!\%(\h\|[^\x01-\x7f]\)\%(\w\|[^\x01-\x7f]\)*/
syn match guttaSymbolDecl /^\s*\zs\%(\h\|[^\x01-\x7f]\)\%(\w\|[^\x01-\x7f]\)*\ze\s*[:,]/
syn match guttaKey /^\s*\zs\%(PORT\d\+\.\)\=\h\w*\ze\s*=/
syn match guttaLocal /#\%(\h\|[^\x01-\x7f]\)\%(\w\|[^\x01-\x7f]\)*/

syn match guttaNumber /\%([[:alnum:]_#.]\)\@<![+-]\=\d[0-9_]*\>/
syn match guttaNumber /\%([[:alnum:]_#.]\)\@<![+-]\=\d[0-9_]*\.\d[0-9_]*\%(e[+-]\=\d\+\)\=\>/
syn match guttaNumber /\%([[:alnum:]_#.]\)\@<![+-]\=\%(2\|8\|10\|16\)#\x[0-9a-f_]*\>/
syn match guttaAddress /\%([[:alnum:]_#]\)\@<!\%(AI\|AQ\|SM\|HC\|I\|Q\|M\|V\|T\|C\|J\|K\|L\)[BWD]\=\d\+\%(\.\d\+\)\=\>/
syn match guttaOperator /[&*]\ze\s*[#[:alpha:]_]/

" Mnemonics: the first word of a line, followed by a blank, `//`, `;`, `,` or the line's
" end, on a line that declares nothing (no `:` before a comment: `Stop : I0.1` is a
" symbol, not STOP).
" BEGIN GENERATED MNEMONICS
" Generated from the stdlib instruction set by lsp/tests/neovim_filetype.rs:
" UPDATE_DOCS=1 cargo test -p gutta-lsp --test neovim_filetype
syn match guttaMnemonic /^\s*\zs\%(BITIM\|CEVNT\|CITIM\|CRETI\|FND<>\|LDB<=\|LDB<>\|LDB>=\|LDD<=\|LDD<>\|LDD>=\|LDR<=\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(LDR<>\|LDR>=\|LDW<=\|LDW<>\|LDW>=\|ROUND\|TRUNC\|AB<=\|AB<>\|AB>=\|AD<=\|AD<>\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(AD>=\|ANDB\|ANDD\|ANDW\|AR<=\|AR<>\|AR>=\|ATCH\|AW<=\|AW<>\|AW>=\|BCDI\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(CALL\|CRET\|CTUD\|DECB\|DECD\|DECO\|DECW\|DISI\|DTCH\|ENCO\|EXCH\|FIFO\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(FILL\|FND<\|FND=\|FND>\|IBCD\|INCB\|INCD\|INCW\|INVB\|INVD\|INVW\|LDB<\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(LDB=\|LDB>\|LDD<\|LDD=\|LDD>\|LDNI\|LDR<\|LDR=\|LDR>\|LDW<\|LDW=\|LDW>\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(LIFO\|MOVB\|MOVD\|MOVR\|MOVW\|NEXT\|OB<=\|OB<>\|OB>=\|OD<=\|OD<>\|OD>=\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(OR<=\|OR<>\|OR>=\|OW<=\|OW<>\|OW>=\|RETI\|SHRB\|SQRT\|STOP\|SWAP\|TONR\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(XORB\|XORD\|XORW\|AB<\|AB=\|AB>\|AD<\|AD=\|AD>\|ALD\|ANI\|AR<\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(AR=\|AR>\|ATH\|ATT\|AW<\|AW=\|AW>\|BIR\|BIW\|BMB\|BMD\|BMW\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(BTI\|COS\|CTD\|CTU\|DIV\|DTA\|DTI\|DTR\|END\|ENI\|EXP\|FOR\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(HTA\|ITA\|ITB\|ITD\|JMP\|LBL\|LDI\|LDN\|LDS\|LPP\|LPS\|LRD\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(MUL\|NOP\|NOT\|OB<\|OB=\|OB>\|OD<\|OD=\|OD>\|OLD\|ONI\|OR<\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(OR=\|OR>\|ORB\|ORD\|ORW\|OW<\|OW=\|OW>\|RET\|RLB\|RLD\|RLW\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(RRB\|RRD\|RRW\|RTA\|SEG\|SIN\|SLB\|SLD\|SLW\|SRB\|SRD\|SRW\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(TAN\|TOF\|TON\|WDR\|\*D\|\*I\|\*R\|+D\|+I\|+R\|-D\|-I\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(-R\|\/D\|\/I\|\/R\|=I\|AI\|AN\|ED\|EU\|LD\|LN\|OI\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
syn match guttaMnemonic /^\s*\zs\%(ON\|RI\|SI\|=\|A\|O\|R\|S\)\ze\%(\s\|\/\/\|;\|,\|$\)\%([^:\/]*:\)\@!/
" END GENERATED MNEMONICS

syn keyword guttaBlock ORGANIZATION_BLOCK SUBROUTINE_BLOCK INTERRUPT_BLOCK DATA_BLOCK
      \ nextgroup=guttaBlockName skipwhite
syn keyword guttaBlock END_ORGANIZATION_BLOCK END_SUBROUTINE_BLOCK END_INTERRUPT_BLOCK
      \ END_DATA_BLOCK SYSTEM_BLOCK END_SYSTEM_BLOCK SYMBOLS END_SYMBOLS BEGIN
      \ VAR VAR_INPUT VAR_OUTPUT VAR_IN_OUT VAR_TEMP END_VAR
syn match guttaBlockName /\%(\h\|[^\x01-\x7f]\)\%(\w\|[^\x01-\x7f]\)*\%(\s*:\s*\%(OB\|SBR\|INT\|DAT\)\d\+\)\=/ contained
syn keyword guttaNetwork NETWORK nextgroup=guttaNetworkNumber skipwhite
syn match guttaNetworkNumber /\d\+/ contained
syn match guttaTitle /^\s*\zsTITLE=/ nextgroup=guttaTitleText
syn match guttaTitleText /.*$/ contained
syn keyword guttaDirective PLC_TYPE nextgroup=guttaPlcType skipwhite
syn match guttaPlcType /[^[:space:]\/]\+/ contained
syn keyword guttaType BOOL BYTE WORD DWORD SINT INT DINT USINT UINT UDINT REAL

syn region guttaString start=/"/ skip=/\\[\\"]/ end=/"/ oneline
syn keyword guttaTodo TODO FIXME XXX contained
syn match guttaComment +//.*$+ contains=guttaTodo,@Spell

hi def link guttaSymbol Identifier
hi def link guttaSymbolDecl Function
hi def link guttaKey Identifier
hi def link guttaLocal Identifier
hi def link guttaNumber Number
hi def link guttaAddress Constant
hi def link guttaOperator Operator
hi def link guttaMnemonic Statement
hi def link guttaBlock Structure
hi def link guttaBlockName Function
hi def link guttaNetwork Label
hi def link guttaNetworkNumber Number
hi def link guttaTitle Keyword
hi def link guttaTitleText Title
hi def link guttaDirective PreProc
hi def link guttaPlcType Constant
hi def link guttaType Type
hi def link guttaString String
hi def link guttaTodo Todo
hi def link guttaComment Comment

let b:current_syntax = 'gutta'
