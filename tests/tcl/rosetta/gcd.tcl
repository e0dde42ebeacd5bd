proc gcd {a b} { while {$b} { lassign [list $b [expr {$a % $b}]] a b }; return [expr {abs($a)}] }
proc lcm {a b} { expr {$a / [gcd $a $b] * $b} }
foreach {a b} {12 18 1071 1029 0 5 -12 18 123456789012345678901234567890 987654321098765432109876543210} {
    puts "gcd($a,$b) = [gcd $a $b]  lcm = [lcm $a $b]"
}
