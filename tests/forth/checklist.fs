\ The F83 checklist of tests/test_f83_checklist.py, typed at the prompt.
40000 .
40000 U.
1.2 .S
DPL @ .
2DROP -9.999 D.
DPL @ .
725 DPL @ .
DROP RCL-LITERALS OFF
: X 1.25 ;  7 X DPL @ .
2DROP DROP RCL-LITERALS ON
5 NOT .
0 NOT .
-7 2 / .
-7 2 MOD .
: DOWN10  0 10 DO I . -1 +LOOP ;
DOWN10
foo
: A 1 ; : A 2 ;
7 0 / .
7 0 MOD .
