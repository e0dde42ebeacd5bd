set x [expr {1 +}]
