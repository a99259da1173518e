\ Kernel: the standard tester's variables and TESTING (T{ -> }T are
\ primitives, rcl/words/tester.py, so each result knows its file and line).
VARIABLE #ERRORS   0 #ERRORS !     \ failed T{ }T lines since the last reset
VARIABLE VERBOSE   0 VERBOSE !     \ true: TESTING shows what is being tested
: TESTING  ( -- )   \ the rest of the line says what is tested next
   SOURCE VERBOSE @ IF  DUP >R TYPE CR R> >IN !  ELSE  >IN ! DROP  THEN ;
