% The arcs at input corners divided in equal segments, their chords
% taking the corners as they fall (see arc_corner_chord, kb/strategy.pl).
bound(arc_corner_chord, 0).
