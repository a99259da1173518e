\ Layer 5, numeric input: the last number typed as fixed point.
\ Adds EXTRACT BUILD SCALAR (FIXED) FIXED FRACTION >V4 UT* UT+ UT/ R*/.
\ Relies on F83's DPL (digits after the last punctuation of the last
\ number, -1 for a single), WIDE-NUMBER (on when that single was typed
\ beyond a signed cell: 40000 would read as -25536) and the double words.
\ A FIXED pair is ( frac int ): the fraction in ten-thousandths and the
\ integer part, both signed: -9.999 is -9990 -9. Above this layer values
\ are V4 = int x 10000 + frac, a double.
: EXTRACT  ( ud k -- u_k ... u_1 int )   \ strip k decimal digits, lowest first
   0 ?DO  10 MU/MOD  LOOP                   ( digits... ud-int )
   ABORT" Out of range"  DUP 0< ABORT" Out of range" ;
: BUILD  ( u_k ... u_1 k -- f )   \ the digits again, u_1 most significant
   0 SWAP 0 ?DO  10 * +  LOOP ;
: SCALAR  ( k -- m )   \ 10^(4-k): rebuilt digits to ten-thousandths
   1 SWAP 4 SWAP - 0 ?DO 10 * LOOP ;
: (FIXED)  ( d dpl -- frac int )   \ any number, with its DPL
   0 MAX  DUP 4 > ABORT" Too many decimals"
   >R  DUP >R DABS  R> R> SWAP >R           ( ud k ) ( R: sign )
   DUP >R EXTRACT  R> SWAP >R               ( digits k ) ( R: sign int )
   DUP >R BUILD R> SCALAR *  R>              ( frac int )
   R> 0< IF NEGATE SWAP NEGATE SWAP THEN ;
: FIXED  ( num -- frac int )   \ the last number typed (DPL tells its size)
   DPL @  WIDE-NUMBER @   \ first: with RCL literals every literal below resets them
   ABORT" Out of range"  BASE @ 10 <> ABORT" Not decimal"
   DUP 0< IF DROP 0 SWAP ELSE (FIXED) THEN ;
: FRACTION  ( frac int mult -- d )   \ sign x (|int| x mult + |frac| x mult / 10000)
   ROT ROT 2DUP OR >R                        ( mult frac int ) ( R: sign )
   ABS 2 PICK UM*  ROT ABS 3 PICK UM* 10000 UM/MOD NIP  0 D+  ROT DROP
   R> 0< IF DNEGATE THEN ;
: >V4  ( frac int -- d )   10000 FRACTION ;

\ Unsigned triples ( t0 t1 t2 ), lowest cell first, for products that
\ outgrow a double: ud x u is at most 48 bits.
: UT*  ( ud u -- ut )   TUCK UM* 2>R  UM*  0 2R> D+ ;
: UT+  ( ut u -- ut' )   3 ROLL 0 ROT 0 D+  >R -ROT R> 0 D+ ;
: UT/  ( ut u -- ut' )   \ long division, high cell first
   >R  0 R@ UM/MOD  R> SWAP >R >R        ( t0 t1 r2 ) ( R: q2 u )
   R@ UM/MOD  R> SWAP >R >R              ( t0 r1 ) ( R: q2 q1 u )
   R> UM/MOD NIP  R> R> ;

\ d x n1 / n2 (n1 >= 0, n2 > 0) rounded half away from zero: on the
\ magnitude, (|d| x n1 + n2/2) / n2 in triples, so nothing wraps; a result
\ beyond a signed double is refused.
: R*/  ( d n1 n2 -- d' )
   >R >R  2DUP D0< -ROT DABS              ( sign ud ) ( R: n2 n1 )
   R> UT*  R@ 2/ UT+  R> UT/               ( sign q0 q1 q2 )
   OVER 0< OR ABORT" Out of range"
   ROT IF DNEGATE THEN ;
