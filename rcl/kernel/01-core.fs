\ Kernel: core words simplest said in Forth.
32 CONSTANT BL             \ ( -- c ) the blank
: END-CODE  ( -- )  ;      \ CODE skips to here; alone it does nothing
: C;  ( -- )  ;
: BOUNDS  ( addr n -- addr+n addr )  OVER + SWAP ;
: FLIP  ( n -- n' )  DUP 8 RSHIFT SWAP 8 LSHIFT OR ;     \ swap the two bytes
: ?COMP  ( -- )  STATE @ 0= ABORT" Compilation Only" ;
: ?EXEC  ( -- )  STATE @ ABORT" Execution Only" ;
: !CSP  ( -- )  DEPTH CSP ! ;
: ?CSP  ( -- )  DEPTH CSP @ <> ABORT" Stack Changed" ;
: BODY>  ( pfa -- xt )  2- ;
: LINK>  ( lfa -- xt )  2+ ;
: HIDE  ( -- )  LAST @ 1- DUP C@ 32 OR SWAP C! ;         \ the newest word
: REVEAL  ( -- )  LAST @ 1- DUP C@ 223 AND SWAP C! ;     \ can't be found / can
