proc f {} {f}
puts [catch f m]
puts $m
f
