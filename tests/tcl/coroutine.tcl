proc gen {n} { yield [info coroutine]; for {set i 0} {$i < $n} {incr i} { yield $i }; return done }
puts [coroutine g gen 3]
puts [g]; puts [g]; puts [g]; puts [g]
puts [info commands g]
puts [catch {g} m]; puts $m
proc acc {} { set total 0; while 1 { set x [yield $total]; incr total $x } }
coroutine a acc
foreach v {1 2 3 4} { puts [a $v] }
puts [info level]; puts [info coroutine]
proc lv {} { yield [info level]; yield [uplevel 1 {info level}]; return [info level] }
coroutine l lv
puts [l]; puts [l]
rename a {}
puts [info commands a]
puts [catch {yield 1} m]; puts "$m $::errorCode"
proc boom {} { yield 1; error "inside" }
coroutine b boom
puts [catch {b} m]; puts $m
puts $::errorInfo
# a coroutine that resumes another
proc inner {} { yield i1; yield i2 }
proc outer {} { coroutine in inner; yield [in]; yield [in] }
coroutine o outer
puts [o]; puts [o]
proc deep {n} { if {$n == 0} { yield bottom; return 0 }; return [expr {1 + [deep [expr {$n-1}]]}] }
puts [coroutine d deep 200]
puts [d]
puts [info commands d]
puts [catch {coroutine x gen 1 2} m]; puts $m
proc ytt {} { set r [yieldto list a b]; return "got $r" }
puts [coroutine y ytt]
puts [y p q]
namespace eval ns { proc g2 {} { yield [info coroutine]; return [namespace current] } }
puts [coroutine ns::c ns::g2]; puts [ns::c]
# A deleted coroutine's stack unwinds: the unset traces of its locals run.
proc keeper {} { set v 1; trace add variable v unset {apply {{a b c} {puts "unwound $a"}}}; yield 1; yield 2 }
coroutine k keeper
rename k {}
puts [info commands k]
# Many coroutines alive at once, each suspended.
for {set i 0} {$i < 200} {incr i} { coroutine c$i apply {{n} { yield; yield [expr {$n * 2}] }} $i }
set s 0
for {set i 0} {$i < 200} {incr i} { incr s [c$i] }
puts $s
