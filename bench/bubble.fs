\ bubble.fs: bubble sort of 200 cells filled by a 15-bit linear congruential
\ generator, 50 times over fresh data, each result checked.
\ Portable to gforth and F83: the cell size is measured (2 on F83, 8 on a
\ 64-bit gforth; F83 has no CELLS), the generator works modulo 2^15 so every
\ stored value is a non-negative 16-bit number, and the comparisons are signed
\ on small positives only. The loops run over addresses with +LOOP.
\ Expected output: CHECKSUM 13585

HERE 0 , HERE SWAP - CONSTANT CELLSIZE    \ bytes per cell
200 CONSTANT #ITEMS
CREATE ITEMS  #ITEMS CELLSIZE * ALLOT
VARIABLE SEED

: RANDOM  ( -- u )   \ x' = (25173 x + 13849) mod 32768, full period
   SEED @ 25173 * 13849 + 32767 AND  DUP SEED ! ;

: ITEM  ( i -- addr )  CELLSIZE * ITEMS + ;

: FILL-ITEMS  ( -- )
   #ITEMS ITEM ITEMS DO  RANDOM I !  CELLSIZE +LOOP ;

: SORT  ( -- )   \ after pass i the last i cells are in place
   #ITEMS 1 DO
      #ITEMS I - ITEM ITEMS DO                   \ I = address of a cell
         I @  I CELLSIZE + @  2DUP > IF          \ a b, a > b: swap
            I !  I CELLSIZE + !
         ELSE
            2DROP
         THEN
      CELLSIZE +LOOP
   LOOP ;

: SORTED?  ( -- -1|0 )
   -1  #ITEMS 1 - ITEM ITEMS DO
      I @  I CELLSIZE + @  > IF DROP 0 THEN
   CELLSIZE +LOOP ;

: CHECK  ( acc -- acc' )   \ add smallest, median, largest, sorted flag
   0 ITEM @ +  #ITEMS 2 / ITEM @ +  #ITEMS 1 - ITEM @ +  SORTED? +
   32767 AND ;

: BUBBLE-BENCH  ( -- n )
   1 SEED !  0
   50 0 DO  FILL-ITEMS SORT CHECK  LOOP ;

: REPORT  ( n -- )  CR ." CHECKSUM " . CR ;

BUBBLE-BENCH REPORT
