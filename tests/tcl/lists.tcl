puts [list a "b c" {} \{ \} "x\\" {$y} {#a} b #c "a\nb" a{b} {[x]} "{a}b" {a {b}} "\{a" {x\y} "a}" "\"a" "a;b" "\ta" a\"b]
puts [list #a #b][list "" #b]
puts [list "a b" "{x" "x}" "}{" "\\" "a\\" "\\n"]
set l {a b {c d} e}
puts [llength $l][lindex $l 2][lindex $l end][lindex $l end-1][lindex $l 10]|[lindex $l -1]|
puts [lindex {{a b} {c d}} 1 0][lindex {{a b} {c d}} {1 1}][lindex $l]
puts [lrange $l 1 2]|[lrange $l 2 end]|[lrange $l -5 0]|[lrange $l 3 1]|
lappend l f g; puts $l; lappend newvar x; puts $newvar
puts [linsert {a b c} 1 X Y][linsert {a b c} end Z][linsert {a b c} 0 W]
puts [lreplace {a b c d} 1 2 X][lreplace {a b c d} 1 1][lreplace {a b c d} 0 0 X Y Z]
puts [lsort {banana apple Cherry date}]
puts [lsort -decreasing {3 1 2}][lsort -integer {10 9 100 1}][lsort -real {1.5 -2 0.25}]
puts [lsort -dictionary {a10 a9 A1 b2 a2 B1}]
puts [lsort -unique {c a b a c}][lsort -nocase {b A c}][lsort -index 1 {{a 3} {b 1} {c 2}}]
proc cmp {a b} { expr {[string length $a] - [string length $b]} }
puts [lsort -command cmp {ccc a bb}]
puts [lsearch {a b c b} b][lsearch {a b c} z][lsearch -exact {a* b} a*][lsearch -glob {abc xyz} x*]
puts [lsearch -all {a b c b} b]|[lsearch -inline {apple banana} b*]|[lsearch -not {a a b} a]|[lsearch -all -inline {a1 b1 a2} a*]
puts [lreverse {1 2 3}][lrepeat 3 a b][concat a {b c} {} " d "][concat]
puts [join {a b c} ,][join {a b c}][join {} -][join {{a b} c} +]
puts [split "a,b,,c" ,]|[split "a b  c"]|[split abc {}]|[split "a.b-c" .-]|[split "" ,]|
lassign {1 2 3 4} p q; puts "$p $q"; puts [lassign {1 2 3} x y z w]|$w|
set m {a b c}; lset m 1 X; puts $m; set nest {{a b} {c d}}; lset nest 1 0 Z; puts $nest
puts [llength "a {b c} \"d e\" f\\ g"]
puts [lindex "a {b c} \"d e\" f\\ g" 3]
foreach bad {"a {b" "a \"b" "{a}b" "\"a\"b"} { puts [catch {llength $bad} msg]:$msg }
set big {}; for {set i 0} {$i < 1000} {incr i} { lappend big $i }; puts [llength $big][lindex $big 999]
puts [list [list a b] [list c [list d e]]]
