% a grading ratio no edge reaches: no transition anywhere (built in: 1.5)
bound(coarsen_ratio, 1000).
