# dict (issue "Tcl 8.6"): every subcommand, nested keys, errors.
catch {dict foo} e; puts $e
catch {dict get {a 1} b} e; puts $e
catch {dict get {a 1 b} b} e; puts $e
catch {dict get} e; puts $e
set d {a 1 b 2}
catch {dict set} e; puts $e
dict set d c d e 5; puts $d
catch {dict set d a x 3} e; puts $e
catch {dict incr d a x} e; puts $e
puts [dict create a 1 a 2 b 3]
puts [dict merge {a 1 b 2} {b 3 c 4}]
catch {dict unset d c q r} e; puts $e
puts [dict filter {a 1 b 2 ab 3} key a*]
puts [dict filter {a 1 b 2 ab 3} value 2]
puts [dict filter {a 1 b 2 ab 3} script {k v} {expr {$v > 1}}]
puts [dict map {k v} {a 1 b 2} {expr {$v * 2}}]
set x {a 1 b 2}
dict with x { set a 10; set c 5 }; puts $x
dict update x a aa b bb { set aa 7; unset bb }; puts $x
puts [dict exists {a 1} a b]
puts [dict exists {a {b 1}} a b]
catch {dict for {k} {a 1} {}} e; puts $e
dict for {k v} {x 1 y 2 z 3} { if {$k eq "y"} continue; puts "$k=$v" }
set cfg [dict create width 640 height 480]
dict incr cfg width 10; dict lappend cfg tags a b; dict append cfg name ray shell
puts $cfg
puts [dict keys $cfg h*]; puts [dict values $cfg]; puts [dict size $cfg]
puts [dict get $cfg]
puts [dict remove $cfg width tags]; puts [dict replace $cfg width 1 new 2]
set n {a {b {c 1}}}
dict with n a b { set c 2 }; puts $n
puts [dict get {a {b {c 1}}} a b c]
catch {dict get {a 1} a b} e; puts $e
puts [catch {dict with nosuch {}} e]; puts $e
