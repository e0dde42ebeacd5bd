proc add {a b} { expr {$a + $b} }
puts [add 2 3]
proc greet {name {greeting Hello}} { return "$greeting, $name!" }
puts [greet World][greet You Hi]
proc sum args { set t 0; foreach a $args { incr t $a }; return $t }
puts [sum][sum 1 2 3]
proc fact n { if {$n <= 1} { return 1 }; expr {$n * [fact [expr {$n - 1}]]} }
puts [fact 20]
proc fib n { if {$n < 2} { return $n }; expr {[fib [expr {$n-1}]] + [fib [expr {$n-2}]]} }
puts [fib 15]
set g 10
proc useglobal {} { global g; incr g; return $g }
puts [useglobal]$g
proc setup {varname} { upvar $varname v; set v "set by proc" }
setup target; puts $target
proc up2 {} { upvar #0 g gg; set gg 99 }; up2; puts $g
proc level1 {} { level2 }
proc level2 {} { uplevel 1 {set fromlevel2 yes}; return [info level] }
proc caller {} { level1; return [info exists fromlevel2] }
puts [caller]
proc counter {} { uplevel #0 {incr g} }; counter; puts $g
proc early {} { foreach x {1 2 3} { if {$x == 2} { return $x } }; return none }
puts [early]
proc noreturn {} { set x 5 }; puts [noreturn]
puts [catch {add 1} msg]$msg
puts [catch {add 1 2 3} msg]$msg
puts [catch {greet} msg]$msg
puts [catch {sum2} msg]$msg
proc deep n { deep [incr n] }
puts [catch {deep 0} msg]$msg
puts [info procs add][lsort [info args greet]][info body add]
puts [info default greet greeting d]$d[info default greet name d2]
proc lvl {} { info level }; puts [lvl][info level]
proc argsof {a b} { info level 0 }; puts [argsof x y]
rename add plus; puts [plus 1 1]; puts [catch {add 1 1} m]$m
proc retcode {} { return -code error "custom failure" }
puts [catch retcode m]$m
proc brk {} { break }; puts [catch brk m]$m
proc loc {} { set a 1; set b 2; info locals }; puts [lsort [loc]]
proc localtest {} { set local 1; return [info exists g] }; puts [localtest]
set counter 0
proc bump {} { global counter; incr counter }
for {set i 0} {$i < 100} {incr i} { bump }
puts $counter
