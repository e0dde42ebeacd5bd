puts [catch {nosuch 1} m]; puts $m
proc unknown {args} { return "unknown got: $args" }
puts [nosuch 1 {2 3}]
rename unknown {}
puts [catch {nosuch} m]; puts $m
