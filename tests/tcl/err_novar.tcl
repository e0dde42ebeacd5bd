puts [set x 1]
set y
