# Recursive fib 27 (635,621 calls): proc calls, if, expr, return.
# ops: 635621 calls
proc fib {n} {
    if {$n < 2} { return $n }
    return [expr {[fib [expr {$n - 1}]] + [fib [expr {$n - 2}]]}]
}
puts [fib 27]
