proc show {args} { puts "trace: $args" }
set x 1
trace add variable x {read write unset} show
set x 2
puts [set x]
incr x
append x a
puts [trace info variable x]
unset x
puts [info exists x]
array set a {1 one 2 two}
trace add variable a {write read array unset} show
set a(3) three
puts $a(1)
array names a
array set a {4 four}
unset a(2)
trace add variable b(k) write show
set b(k) 1
set b(j) 2
proc p {} { set y 1; trace add variable y unset show; set y 2; return ok }
puts [p]
proc clamp {n1 n2 op} { upvar $n1 v; if {$v > 10} { set v 10 } }
set z 0
trace add variable z write clamp
puts [set z 50]
puts $z
proc bad {args} { error "no way" }
set w 1
trace add variable w write bad
puts [catch {set w 2} m]; puts $m
puts $::errorInfo
trace remove variable w write bad
set w 3; puts $w
trace variable q w show
set q 1
puts [trace vinfo q]
proc foo {a} { return [expr {$a*2}] }
trace add execution foo {enter leave} show
foo 3
trace add command foo {rename delete} show
rename foo bar
rename bar {}
proc st {} { set a 1; incr a; return $a }
trace add execution st {enterstep leavestep} show
st
# A trace that fails stops the write, with Tcl's wording.
proc ro {n1 n2 op} { error "read-only" }
set frozen 1
trace add variable frozen write ro
puts [catch {set frozen 2} m]; puts $m
# Unset traces of a proc's locals run when it returns, in its caller.
proc locals {} { set v 1; trace add variable v unset {apply {{a b c} {puts "gone: $a [info level]"}}} }
locals
# Old-style traces and their letters.
trace variable old rw {apply {{a b op} {puts "old $a $op"}}}
set old 1; set old
puts [trace vinfo old]
trace vdelete old rw {apply {{a b op} {puts "old $a $op"}}}
puts [trace vinfo old]
# Element traces; array traces see each element of array set.
array set arr {}
trace add variable arr(k) {write unset} show
set arr(k) 1; set arr(j) 2; unset arr
puts [catch {trace add variable old(x) write show} m]; puts $m
puts [catch {trace add variable zz bogus show} m]; puts $m
puts [catch {trace add command nosuch delete show} m]; puts $m
