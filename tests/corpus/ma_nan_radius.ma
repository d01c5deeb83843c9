1 0 0
v 0 0 0 nan
