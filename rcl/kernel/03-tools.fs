\ Kernel: F83's ASSEMBLER and EDITOR vocabularies (Forth 2012 Tools), and
\ the Facility word set's structures, which are simplest said in Forth.
VOCABULARY ASSEMBLER    \ CODE skips assembler text: this list stays empty
VOCABULARY EDITOR       \ the line editor's words go here
: BEGIN-STRUCTURE  ( -- addr 0 )   \ name: ( -- u ) the structure's size
   CREATE HERE 0 0 ,  DOES> @ ;
: END-STRUCTURE  ( addr u -- )   SWAP ! ;
: +FIELD  ( n1 n2 -- n3 )   \ name: ( addr -- addr+n1 )
   CREATE OVER , +  DOES> @ + ;
: FIELD:  ( n1 -- n2 )   2 +FIELD ;        \ a cell (cells need no alignment)
: CFIELD:  ( n1 -- n2 )   1 +FIELD ;       \ a character
\ Forth 2012 has every standard word in FORTH-WORDLIST: the search-order
\ words F83 keeps in ROOT are found from FORTH too (ROOT keeps its own).
SYNONYM FORTH-WORDLIST FORTH-WORDLIST   SYNONYM GET-ORDER GET-ORDER
SYNONYM SET-ORDER SET-ORDER   SYNONYM ALSO ALSO   SYNONYM ONLY ONLY
SYNONYM PREVIOUS PREVIOUS   SYNONYM DEFINITIONS DEFINITIONS   SYNONYM ORDER ORDER
