/** Sharp corners: a design rule the paper does not have.

b6: a sharp corner of the front (theta1 below 60 deg) between open nodes.
The paper's b2 answers a2(180 - theta1, 180 - theta1): a parallelogram,
whose corner opposite N1 is as sharp as theta1 and whose corners at N2
and N4 are obtuse (above 120 deg for theta1 below 60). b6 stands the
element's sides at N2 and N4 at right angles to the front instead: a
right trapezoid with one sharp corner (the input's own) and three good
ones, and the front it leaves keeps straight angles at N2 and N4.

    freemesh mesh examples/plugger.json -o before.svg
    freemesh mesh examples/plugger.json --kb examples/kb/sharp-corner.pl -o after.svg

```
?- feature(b6, ctx(180, 180, 40, 180, 180, 1, 1, 1)).
   true.
?- context_design(ctx(180, 180, 40, 180, 180, 1, 1, 1), F, A).
   F = b6, A = a2(90, 90).
```
*/

%% feature(b6, +Ctx): theta1 below 60 with open nodes N2 and N4 beside it
%% (between 160 and 200 deg: on a nearly straight side).
feature(b6, ctx(_, T4, T1, T2, _, _, _, _)) :-
    T1 < 60, open_side_(T2), open_side_(T4).

open_side_(T) :- T >= 160, T =< 200.

% a2 with right angles at N2 and N4.
feature_action(b6, _, a2(90, 90)).

% The paper's order, with the new feature first.
strategy([b6, b4, b5, b3, b2, b1]).
