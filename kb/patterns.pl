/** Final patterns: closing a loop of four or six segments (Fig. 16).

The host asks with the interior angles of the loop's nodes, A1..A6 in
loop order, and tries the answers in order: it keeps the first whose
elements are valid with every corner inside [lower_corner, upper_corner]
(bound/2), else the valid one whose worst corner is nearest that window:

  quad                a four-segment loop is the last element itself
  pattern1(K)         new node at (X2+X4+X6)/3 of the nodes K+1, K+3, K+5
                      (Eq. 5), linked to them: three elements
  pattern2(K)         new node at (3X3+3X5+X2+X6)/8 (Eq. 6), nodes counted
                      from K, linked to the nodes K+1, K+3, K+5
  pattern3(K)         link the nodes K+2 and K+5 (Fig. 16(c)): two elements

(K rotates the paper's numbering round the loop, 0-based.)

```
?- loop_patterns([90, 90, 180, 90, 90, 180], [P | _]).
   P = pattern3(0).
```
*/

:- dynamic(final_pattern/3).
:- dynamic(closing_way/2).

%% final_pattern(+Angles, ?K, -Pattern)
%
% Pattern closes a six-segment loop with interior Angles, rotated by K
% (the last clauses offer every pattern again, as a last try).
% ?- final_pattern([120, 120, 120, 120, 120, 120], 0, P).
%    P = pattern1(0) ;  P = pattern3(0) ;  P = pattern1(0) ;  false.

% Pattern 3: the two straight nodes of a 2 x 1 block face each other.
final_pattern(As, K, pattern3(K)) :-
    rotation_(K), rotated_(As, K, [_, _, A3, _, _, A6]),
    A3 >= 150, A6 >= 150.
% Pattern 2: one open node faces an edge (a trapezoid): the new node
% leans towards N3 and N5.
final_pattern(As, K, pattern2(K)) :-
    rotation_(K), rotated_(As, K, [_, _, A3, A4, A5, _]),
    A4 >= 150, A3 < 150, A5 < 150.
% Pattern 1: three corners alternate with three open nodes.
final_pattern(As, K, pattern1(K)) :-
    member(K, [0, 1]), rotated_(As, K, [A1, A2, A3, A4, A5, A6]),
    A2 + A4 + A6 >= A1 + A3 + A5.
% Anything else: try every pattern in turn (the host's choice above).
final_pattern(_, K, pattern3(K)) :- rotation_(K).
final_pattern(_, K, pattern1(K)) :- member(K, [0, 1]).

rotation_(K) :- member(K, [0, 1, 2, 3, 4, 5]).

rotated_(As, K, Rs) :-
    length(Front, K), append(Front, Back, As), append(Back, Front, Rs).

%% loop_patterns(+Angles, -Patterns)
%
% Every pattern the rules allow for the loop, best first.
% ?- loop_patterns([90, 90, 180, 90, 90, 180], [P | _]).
%    P = pattern3(0).
loop_patterns(As, Ps) :-
    findall(P, final_pattern(As, _, P), Ps).

%% closing_way(+Segments, ?Way)
%
% Where no rule applies and a loop of at most
% bound(closing_loop_segments, _) segments is left, the host closes it
% whole by the best of the ways allowed here (its worst element nearest
% a square; the new nodes placed by a search); the smaller loops a chord
% or a path leaves are closed the same way, by the ways for their own
% number of segments:
%
%   quad    a four-segment loop is one element
%   inset   a four-segment loop gets a quad inside it and four round it
%           (a loop that is no element: a triangle with a node on a side)
%   hub     a new node linked to every other node of the loop
%   chord   a chord between two nodes parts the loop in two
%   path    a path of two segments through a new node parts it in two
%           (a block of 2 x 3 elements is a path and a hub)
%
% ?- findall(W, closing_way(8, W), Ws).
%    Ws = [hub, chord, path].
% ?- findall(W, closing_way(4, W), Ws).
%    Ws = [quad, inset].
closing_way(4, quad).
closing_way(4, inset).
closing_way(N, hub) :- N >= 6.
closing_way(N, chord) :- N >= 6.
closing_way(N, path) :- N >= 8.
