% Block layouts given up sooner (built in: bound(layout_steps, 3)).
bound(layout_steps, 1).
