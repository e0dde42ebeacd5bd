set x 5
if {$x > 3} { puts big } else { puts small }
if {$x > 10} { puts a } elseif {$x > 4} then { puts b } else { puts c }
if 0 { puts no }
puts [if {1} {set r yes}]
for {set i 0} {$i < 10} {incr i} { if {$i == 2} continue; if {$i == 5} break; puts -nonewline "$i " }; puts ""
set n 0; while 1 { incr n; if {$n > 3} break }; puts $n
foreach {a b} {1 2 3 4 5} { puts "$a-$b" }
foreach a {x y z} b {1 2} { puts "$a$b" }
foreach x {} { puts never }
switch foo { bar { puts bar } foo { puts foo } default { puts def } }
switch -glob hello { h*o { puts glob } default { puts no } }
switch xyz { a - b { puts ab } default { puts default } }
switch b a - b - c { puts abc } d { puts d }
switch -exact -- -x { -x { puts dash } }
puts [switch nomatch { a { set z 1 } }]|
puts [catch {error "my error"} msg]$msg
puts [catch {set undefined_var} msg]$msg
puts [catch {return -code break} msg][catch {break}][catch {continue}][catch {return x} msg]$msg
puts [catch {expr 1} r]$r
catch {error boom} m opts; puts [lindex $opts 0][lindex $opts 1]
set r [catch {error "x" "" {MY CODE}} m]; puts "$r $m $errorCode"
puts [eval list a b {c d}][eval {set q 7}]
set code {puts evaluated}; eval $code
puts [lindex [time {set z 1} 10] 1]
puts [info exists x][info exists nope][info complete "set a {"][info complete "set a {}"]
set arr(a) 1; puts [info exists arr(a)][info exists arr(b)][info exists arr]
puts [info commands lsort][info commands nosuch]
puts [expr {[llength [info commands]] > 40}]
