\ Control structures (docs/forth2012.md, Core) and SEE reading them back.
: CLASSIFY  ( n -- )  DUP 0< IF ." negative" ELSE DUP 0= IF ." zero" ELSE ." positive" THEN THEN DROP ;
-5 CLASSIFY
0 CLASSIFY
7 CLASSIFY
: COUNTDOWN  ( n -- )  BEGIN DUP . 1- DUP 0= UNTIL DROP ;
3 COUNTDOWN
: HALVES  ( n -- )  BEGIN DUP WHILE DUP . 2/ REPEAT DROP ;
100 HALVES
: SKIP  10 0 ?DO I 4 = IF LEAVE THEN I . LOOP ;
SKIP
: NONE  0 0 ?DO I . LOOP ." done" ;
NONE
SEE COUNTDOWN
SEE HALVES
SEE CLASSIFY
THEN
