% Boundary nodes stay where the boundary's division put them (built in:
% easing may slide one inside a straight input edge along it).
bound(boundary_slide, 0).
