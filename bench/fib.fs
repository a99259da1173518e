\ fib.fs: doubly recursive Fibonacci, a call/return benchmark.
\ Portable to gforth (64-bit cells) and F83 (16-bit cells): fib(23) = 28657
\ fits a signed 16-bit cell and the running sum is masked to 15 bits.
\ The recursion goes through a vector (FIB-VECTOR @ EXECUTE): RECURSE is
\ ANS, F83 spells it RECURSIVE, and ' EXECUTE ! @ work on every Forth.
\ Per repetition 92,735 calls: 46,367 inner calls and 46,368 leaves.
\ Expected output: CHECKSUM 32528

VARIABLE FIB-VECTOR

: FIB  ( n -- fib[n] )
   DUP 2 < IF EXIT THEN
   DUP 1 -  FIB-VECTOR @ EXECUTE
   SWAP 2 - FIB-VECTOR @ EXECUTE  + ;

' FIB FIB-VECTOR !

: FIB-BENCH  ( -- sum )   \ 16 x fib(23), summed modulo 32768
   0  16 0 DO  23 FIB + 32767 AND  LOOP ;

: REPORT  ( n -- )  CR ." CHECKSUM " . CR ;

FIB-BENCH REPORT
