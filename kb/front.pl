/** The live front: the boundary of the remaining domain as facts, and the
geometric reasoning over it (the vocabulary of `freemesh repl`).

The host states the front of the remaining domain Ω as facts whenever it
changes (a domain is loaded, elements are made):

  node_xy(N, X, Y)        front node N at (X, Y)
  front_edge(N1, N2)      a front edge, the remaining domain on its left
  node_angle(N, Degrees)  interior angle of Ω at N (rounded to a degree)
  edge_context(E, Ctx)    the context term the mesher asks the KB about
                          for the oriented edge E = N1-N2 (features.pl);
                          every front edge is read both ways

The relations below are derived from them, as in the paper's "feature
recognition subsystem": concave points, parallel edges, a node near a
segment (Fig. 10), and each edge's feature and design action.

```
?- concave_point(N).
   N = 12 ;  ...
?- edge_feature(E, F).
   E = 0-1, F = b3 ;  ...
```
*/

:- use_module(library(lists)).

:- dynamic(node_xy/3).
:- dynamic(front_edge/2).
:- dynamic(node_angle/2).
:- dynamic(edge_context/2).

%% concave_point(?N)
%
% True iff front node N is a concave point of the remaining domain.
% ?- concave_point(N).   (on an L-shaped front)
%    N = 3.
concave_point(N) :-
    node_angle(N, Theta),
    angle_concave(Theta).

%% parallel(?E1, ?E2)
%
% True iff the front edges E1 = A-B and E2 = C-D (distinct) lie on
% parallel lines: the paper's theorem A1*B2 = A2*B1 over line equations.
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
near_segment(N, A-B) :-
    front_edge(A, B),
    edge_segment_(A-B, Seg),
    Seg = seg(point(Xa, Ya), point(Xb, Yb)),
    Len is sqrt((Xb - Xa) ** 2 + (Yb - Ya) ** 2),
    node_xy(N, X, Y),
    N \== A, N \== B,
    point_segment_distances(point(X, Y), Seg, V, H),
    point_segment_near(V, H, Len).

%% edge_feature(?E, ?F)
%
% True iff the oriented front edge E = N1-N2 shows boundary feature F,
% features listed in the order of strategy/1.
% ?- edge_feature(0-1, F).
%    F = b3.
edge_feature(E, F) :-
    edge_context(E, Ctx),
    context_feature(Ctx, F).

%% edge_action(?E, ?A)
%
% True iff A is the design action the KB takes on the oriented front edge
% E: the action of its first feature in the strategy.
% ?- edge_action(0-1, A).
%    A = a3.
edge_action(E, A) :-
    edge_context(E, Ctx),
    context_design(Ctx, _, A).

edge_segment_(A-B, seg(point(Xa, Ya), point(Xb, Yb))) :-
    node_xy(A, Xa, Ya),
    node_xy(B, Xb, Yb).
