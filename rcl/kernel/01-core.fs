\ Kernel: core words simplest said in Forth.
32 CONSTANT BL             \ ( -- c ) the blank
: END-CODE  ( -- )  ;      \ CODE skips to here; alone it does nothing
: C;  ( -- )  ;
