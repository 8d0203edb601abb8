/** The live front: the boundary of the remaining domain as facts, and the
geometric reasoning over it (the vocabulary of `freemesh repl`).

The host states the front of the remaining domain Ω as facts whenever it
changes (a domain is loaded, elements are made):

  node_xy(N, X, Y)         front node N at (X, Y)
  front_edge(N1, N2)       a front edge, the remaining domain on its left
  node_angle(N, Degrees)   interior angle of Ω at N (rounded to a degree)
  edge_context(E, N, Ctx)  the context term the mesher asks the KB about
                           for the front edge E = A-B read from its end N
                           (features.pl): from A along the front, and from
                           B mirrored, the front walked backwards, so that
                           a feature anchored at either end is found

The relations below are derived from them, as in the paper's "feature
recognition subsystem": concave points, parallel edges, a node near a
segment (Fig. 10), and each edge's feature and design action. An edge is
always written as the front has it (front_edge(A, B) holds for E = A-B);
where a feature or action is anchored is part of the answer, at(F, N):
N is the end of the edge the feature's labelling starts from (its N1).

The examples are on the L-shaped domain tests/inputs/l-shape.json (32
front segments; the corners at nodes 0, 8, 12, 20 and 24, the concave
corner at node 16), as `freemesh repl tests/inputs/l-shape.json` shows:

```
?- concave_point(N).
   N = 16 ;  false.
?- edge_feature(E, F).
   E = 0-1, F = at(b2, 0) ;  ...
```
*/

:- use_module(library(lists)).

:- dynamic(node_xy/3).
:- dynamic(front_edge/2).
:- dynamic(node_angle/2).
:- dynamic(edge_context/3).

%% concave_point(?N)
%
% True iff front node N is a concave point of the remaining domain.
% ?- concave_point(N).
%    N = 16 ;  false.
concave_point(N) :-
    node_angle(N, Theta),
    angle_concave(Theta).

%% parallel(?E1, ?E2)
%
% True iff the front edges E1 = A-B and E2 = C-D (distinct) lie on
% parallel lines: the paper's theorem A1*B2 = A2*B1 over line equations.
% ?- parallel(0-1, 20-21).
%    true.
% ?- parallel(0-1, 16-17).
%    false.
parallel(A-B, C-D) :-
    front_edge(A, B),
    front_edge(C, D),
    A-B \== C-D,
    edge_segment_(A-B, S1),
    edge_segment_(C-D, S2),
    segments_parallel(S1, S2).

%% near_segment(?N, ?E)
%
% True iff front node N approaches the front edge E = A-B (not one of its
% ends): both its vertical and its horizontal distance to the segment are
% small against the segment's length (Fig. 10).
% ?- near_segment(N, E).
%    false.
near_segment(N, A-B) :-
    front_edge(A, B),
    edge_segment_(A-B, Seg),
    Seg = seg(point(Xa, Ya), point(Xb, Yb)),
    Len is sqrt((Xb - Xa) ** 2 + (Yb - Ya) ** 2),
    node_xy(N, X, Y),
    N \== A, N \== B,
    point_segment_distances(point(X, Y), Seg, V, H),
    point_segment_near(V, H, Len).

%% edge_feature(?E, ?At)
%
% True iff At = at(F, N): the front edge E = A-B, read from its end N (A,
% or B for the mirrored reading), shows boundary feature F; an edge's
% features are listed in the order of strategy/1, the reading from A
% first.
% ?- edge_feature(7-8, F).
%    F = at(b2, 8) ;  false.
% ?- edge_feature(E, at(b2, 16)).
%    false.
edge_feature(A-B, at(F, N)) :-
    front_edge(A, B),
    edge_reading_(A-B, N, Ctx),
    context_feature(Ctx, F).

%% edge_action(?E, ?At)
%
% True iff At = at(Action, N): Action is the design action the KB takes on
% the front edge E = A-B read from its end N, the action of the first
% feature of the strategy the reading shows.
% ?- edge_action(0-1, A).
%    A = at(a2(90, 90), 0) ;  false.
edge_action(A-B, at(Action, N)) :-
    front_edge(A, B),
    edge_reading_(A-B, N, Ctx),
    context_design(Ctx, _, Action).

% The two readings of a front edge, the one from A first.
edge_reading_(A-B, N, Ctx) :-
    (   N = A ; N = B ),
    edge_context(A-B, N, Ctx).

edge_segment_(A-B, seg(point(Xa, Ya), point(Xb, Yb))) :-
    node_xy(A, Xa, Ya),
    node_xy(B, Xb, Yb).
