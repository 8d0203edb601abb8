/** Geometric reasoning: the axioms FREEMESH reasons with.

Points are point(X, Y); segments seg(P, Q). Angles are in degrees.
The host passes numbers already measured on the front (interior angles,
the vertical and horizontal distances of Fig. 10); the predicates here say
what those numbers mean.

```
?- segments_parallel(seg(point(0,0), point(2,0)), seg(point(0,1), point(3,1))).
   true.
?- point_segment_distances(point(3,1), seg(point(0,0), point(2,0)), V, H).
   V = 1.0, H = 1.0.
```

(The KB is loaded into one `user` module, so that a user's --kb file can
add clauses to and replace the settings of the same predicates.)
*/

:- use_module(library(lists)).

%% line_equation(+P1, +P2, -A, -B, -C)
%
% True iff A*X + B*Y + C = 0 is the line through P1 and P2 (the paper's
% find_line_equation).
% ?- line_equation(point(0,0), point(1,1), A, B, C).
%    A = 1, B = -1, C = 0.
line_equation(point(X1, Y1), point(X2, Y2), A, B, C) :-
    A is Y2 - Y1,
    B is X1 - X2,
    C is X2 * Y1 - X1 * Y2.

%% segments_parallel(+Seg1, +Seg2)
%
% True iff the lines of the two segments are parallel: A1*B2 = A2*B1 (the
% paper's theorem), within a relative tolerance for measured coordinates.
% ?- segments_parallel(seg(point(0,0), point(1,0)), seg(point(0,1), point(5,1))).
%    true.
segments_parallel(seg(P1, P2), seg(P3, P4)) :-
    line_equation(P1, P2, A1, B1, _),
    line_equation(P3, P4, A2, B2, _),
    Cross is A1 * B2 - A2 * B1,
    Scale is (abs(A1) + abs(B1)) * (abs(A2) + abs(B2)),
    Scale > 0,
    abs(Cross) =< 1.0e-9 * Scale.

%% angle_concave(+Degrees)
%
% True iff an interior angle of the remaining domain makes its node a
% concave point (the domain bends round it: more than a straight angle).
% ?- angle_concave(200).
%    true.
angle_concave(Theta) :- Theta > 180.

%% point_segment_distances(+Point, +Seg, -Vertical, -Horizontal)
%
% Vertical: distance from Point to the line of Seg. Horizontal: how far
% the foot of Point falls outside Seg along it, 0 when between its ends
% (Fig. 10).
% ?- point_segment_distances(point(1,1), seg(point(0,0), point(2,0)), V, H).
%    V = 1.0, H = 0.
point_segment_distances(point(X, Y), seg(point(X1, Y1), point(X2, Y2)), V, H) :-
    Dx is X2 - X1, Dy is Y2 - Y1,
    Len is sqrt(Dx * Dx + Dy * Dy),
    Len > 0,
    T is ((X - X1) * Dx + (Y - Y1) * Dy) / Len,
    V is abs((X - X1) * Dy - (Y - Y1) * Dx) / Len,
    (   T < 0 -> H is -T
    ;   T > Len -> H is T - Len
    ;   H = 0
    ).

%% point_segment_near(+Vertical, +Horizontal, +Size)
%
% True iff a point at these distances approaches a segment of an element
% of edge length Size: only when both distances are small (Fig. 10).
% ?- point_segment_near(0.1, 0.0, 1.0).
%    true.
% ?- point_segment_near(0.1, 2.0, 1.0).
%    false.
point_segment_near(V, H, Size) :-
    bound(near_vertical, Kv),
    bound(near_horizontal, Kh),
    V < Kv * Size,
    H < Kh * Size.
