\ sieve.fs: byte-array sieve of Eratosthenes over the odd numbers 3..16383
\ (8190 flags, the classic BYTE benchmark), repeated 60 times.
\ Portable to gforth and F83: the largest value ever formed is 24,572,
\ well inside a signed 16-bit cell.
\ Expected output: CHECKSUM 1899  (primes below 16384, excluding 2)

8190 CONSTANT #FLAGS
CREATE FLAGS  #FLAGS ALLOT

: SIEVE  ( -- #primes )
   FLAGS #FLAGS + FLAGS DO  1 I C!  LOOP         \ every flag set
   0  #FLAGS 0 DO                                \ count
      FLAGS I + C@ IF                            \ 2i+3 is prime
         I DUP + 3 +  DUP I +                    \ count prime k
         BEGIN  DUP #FLAGS <  WHILE              \ count prime k
            0 OVER FLAGS + C!  OVER +            \ strike k, k+=prime
         REPEAT
         DROP DROP  1 +
      THEN
   LOOP ;

: SIEVE-BENCH  ( -- #primes )   \ 60 runs, the last count is kept
   0  60 0 DO  DROP SIEVE  LOOP ;

: REPORT  ( n -- )  CR ." CHECKSUM " . CR ;

SIEVE-BENCH REPORT
