/** Initial design: the rules "if b_j then a_k" (Exp. 2) and the actions.

An action term says how to place the element N1N2N3N4 over the edge N1N2
(labelling of features.pl); the host's builtins place the nodes:

  a1(Phi1, Phi2, L2, L4)  add three lines: new N4 at angle Phi1 from N1N2
                          and distance L4 from N1, new N3 at angle Phi2 and
                          distance L2 from N2 (lengths relative to |N1N2|).
  a2(Phi2, Phi4)          add two lines: the quad N1 N2 N3 N4 with N4 the
                          front node before N1; new N3 where the line from
                          N2 at Phi2 meets the line from N4 at Phi4.
  a3                      add one line: link the front nodes after N2 and
                          before N1; the element is N1 N2 N5 N4 (Fig. 7(c)
                          calls the node after N2 "N3").
  a4                      new N3 = (N2 + N4 + N6)/3 with N6 = N5 + N7 - N1,
                          the far corner of the block of Fig. 9(a).

```
?- feature_action(b2, ctx(180, 180, 90, 180, 180, 1, 1), A).
   A = a2(90, 90).
?- context_design(ctx(180, 180, 180, 180, 180, 1, 1), F, A).
   F = b1, A = a1(90.0, 90.0, 1.0, 1.0).
```
*/

:- dynamic(feature_action/3).

%% feature_action(+Feature, +Ctx, -Action)
%
% Action is the design action for an edge with Feature and context Ctx
% (below, the reflex corner of 270 at N2 is shared by three elements).
% ?- feature_action(b1, ctx(180, 180, 180, 270, 180, 1, 1), A).
%    A = a1(90.0, 90.0, 1.0, 1.0).

% a1 for b1: phi = theta/2, l2 = (l1 + l6)/(2 sin phi2),
% l4 = (l5 + l1)/(2 sin phi1). A reflex angle above bound(reflex_split)
% is shared by more elements: phi = theta/k, k = round(theta/90).
feature_action(b1, ctx(_, _, T1, T2, _, L5, L6), a1(Phi1, Phi2, L2, L4)) :-
    corner_share_(T1, Phi1),
    corner_share_(T2, Phi2),
    L2 is (1 + L6) / (2 * sin(Phi2 * pi / 180)),
    L4 is (L5 + 1) / (2 * sin(Phi1 * pi / 180)).
% a2 for b2: phi2 = phi4 = pi - theta1 (a parallelogram).
feature_action(b2, ctx(_, _, T1, _, _, _, _), a2(Phi, Phi)) :-
    Phi is 180 - T1.
% a3 for b3: link N5 (the paper's N3) and N4.
feature_action(b3, _, a3).
% a4 for b4: N3 at the centre of the block.
feature_action(b4, _, a4).
% a5 for b5: phi4 = pi - theta1, phi2 = theta5/(theta1 + theta5) * theta2,
% kept within [30, 150] so that both elements at N2 stay usable.
feature_action(b5, ctx(_, _, T1, T2, T5, _, _), a2(Phi2, Phi4)) :-
    Phi4 is 180 - T1,
    Phi2 is min(150, max(30, T5 / (T1 + T5) * T2)).

corner_share_(Theta, Phi) :-
    bound(reflex_split, R),
    (   Theta =< R -> Phi is Theta / 2
    ;   K is max(2, round(Theta / 90)), Phi is Theta / K
    ).

%% context_design(+Ctx, -Feature, -Action)
%
% The first feature of the strategy the edge shows, and its action.
% ?- context_design(ctx(90, 180, 90, 180, 90, 1, 1), F, A).
%    F = b4, A = a4.
context_design(Ctx, F, A) :-
    context_feature(Ctx, F),
    feature_action(F, Ctx, A),
    !.

%% context_designs(+Ctxs, -Designs)
%
% Batch form for the host: one d(Feature, Action) per context, or none
% when the edge shows no feature.
% ?- context_designs([ctx(180, 180, 180, 180, 180, 1, 1),
%                     ctx(90, 90, 300, 90, 90, 1, 1)], Ds).
%    Ds = [d(b1, a1(90.0, 90.0, 1.0, 1.0)), none].
context_designs([], []).
context_designs([C | Cs], [D | Ds]) :-
    (   context_design(C, F, A) -> D = d(F, A) ; D = none ),
    context_designs(Cs, Ds).
