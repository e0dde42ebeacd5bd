# Integers of any size: literals, arithmetic that overflows 64 bits,
# conversions, comparisons with doubles, format and string is.
puts [expr int(1e300)]
puts [expr wide(1e300)]
puts [expr entier(1e30)]
puts [expr {9007199254740993 == 9007199254740992.0}]
puts [expr {9007199254740993 > 9007199254740992.0}]
puts "[catch {expr 1<<(1<<40)} m] $m"
puts "[catch {expr 2**(1<<40)} m] $m"
puts "[catch {expr 10**100000} m] [string length $m]"
puts [expr {round(1e20)}]
puts [expr {isqrt(10**40)}]
puts [expr {-(1<<63)}]
puts [expr {double(10**400)}]
puts "[catch {expr {double(10**400)}} m] $m"
puts [expr {(1<<64) / 3}]
puts [expr {-(1<<64) % 7}]
puts [expr {abs(-9223372036854775808)}]
puts [format %d [expr 1<<70]]
puts [format %lld [expr 1<<70]]
puts [format %x [expr 1<<70]]
puts [format %llx [expr 1<<70]]
puts [expr {int(1<<70)}]
puts [expr {wide(1<<63)}]
puts [string is integer [expr 1<<70]]
puts [string is wide [expr 1<<70]]
puts [expr {~(1<<70)}]
puts [expr {(1<<70) & -1}]
puts [expr {(1<<70) ^ -(1<<65)}]
puts [expr {(1<<70) >> 3}]
puts [expr {-(1<<70) >> 100}]
puts [incr x [expr 1<<70]]
puts [expr {0x10000000000000000 + 0b1 + 0o77777777777777777777777}]
puts [expr {(1<<70) * 1.5}]
puts [expr {max(1<<70, 1.0)}]
puts [expr {srand(1<<70)}]
puts [format %d 5000000000]
puts [format %ld 5000000000]
puts [format %d [expr 1<<65]]
puts [format %ld [expr 1<<65]]
puts [format %lld -[expr 1<<65]]
puts [format %x -1]
puts [format %lx -1]
puts [format %llx -1]
puts [format %llo [expr 1<<65]]
puts [format %llb [expr 1<<65]]
puts [format %#llx [expr 1<<65]]
puts [format %u -1]
puts [format %e [expr 1<<70]]
puts [format %c 65]
puts [string is integer 5000000000]
puts [string is wide 5000000000]
puts [string is entier [expr 1<<70]]
puts [catch {string repeat a [expr 1<<70]} m] 
puts $m
puts [catch {incr x 1.5} m]; puts $m
set y [expr 1<<70]; puts [catch {incr y 1} m]; puts $m
puts "2147483647 [string is integer 2147483647] [string is wide 2147483647] [string is entier 2147483647]"
puts "2147483648 [string is integer 2147483648] [string is wide 2147483648] [string is entier 2147483648]"
puts "-2147483648 [string is integer -2147483648] [string is wide -2147483648] [string is entier -2147483648]"
puts "-2147483649 [string is integer -2147483649] [string is wide -2147483649] [string is entier -2147483649]"
puts "4294967295 [string is integer 4294967295] [string is wide 4294967295] [string is entier 4294967295]"
puts "4294967296 [string is integer 4294967296] [string is wide 4294967296] [string is entier 4294967296]"
puts "9223372036854775807 [string is integer 9223372036854775807] [string is wide 9223372036854775807] [string is entier 9223372036854775807]"
puts "9223372036854775808 [string is integer 9223372036854775808] [string is wide 9223372036854775808] [string is entier 9223372036854775808]"
puts "0x80000000 [string is integer 0x80000000] [string is wide 0x80000000] [string is entier 0x80000000]"
puts "0xffffffff [string is integer 0xffffffff] [string is wide 0xffffffff] [string is entier 0xffffffff]"
puts "18446744073709551615 [string is integer 18446744073709551615] [string is wide 18446744073709551615] [string is entier 18446744073709551615]"
puts "18446744073709551616 [string is integer 18446744073709551616] [string is wide 18446744073709551616] [string is entier 18446744073709551616]"
puts "-18446744073709551615 [string is integer -18446744073709551615] [string is wide -18446744073709551615] [string is entier -18446744073709551615]"
puts "-18446744073709551616 [string is integer -18446744073709551616] [string is wide -18446744073709551616] [string is entier -18446744073709551616]"
puts "-4294967295 [string is integer -4294967295] [string is wide -4294967295] [string is entier -4294967295]"
puts "-4294967296 [string is integer -4294967296] [string is wide -4294967296] [string is entier -4294967296]"
# NaN operands and math function errors
set n NaN
foreach e {{$n < 1} {$n == $n} {$n != 1} {-$n} {+$n} {!$n} {$n ** 2} {$n % 2} {abs($n)} {double($n)} {sin($n)} {max($n,1)} {int($n)} {$n eq $n} {$n ? 1 : 2} {$n && 1} {round($n)} {isqrt($n)} {entier($n)} {bool($n)} {0**0} {0.0**0} {0**-1} {0.0**-1} {hypot($n,1)} {fmod($n,1)} {Inf - Inf} {Inf * 0} {$n > $n}} {
  catch {expr $e} m; puts "[list $e] -> [list $m]"
}
foreach e {{abs("x")} {sin("x")} {int("x")} {max("x",1)} {round("x")} {double("x")} {bool("x")} {isqrt("x")} {srand("x")} {entier("")} {hypot(1,"x")} {abs()} {max()} {rand(1)}} { catch {expr $e} m; puts "[list $e] -> [list $m]" }
foreach e {{1 x} {1 2} {1 $a} {1.x} {1.5e} {1 (2)} {1.5foo} {1 eq2} {2 in{a b}} {0x1g} {1e5x} {1_0} {_a} {@} {1 @} {a.b} {5 + tcl::mathfunc::abs(1)} {5 + ::tcl::mathfunc::abs(-1)} {"a" eqq "b"} {1 nix 2} {$} {1$} {3 inx}} {
  set a 1
  catch {expr $e} m; puts "[list $e] -> [list $m]"
}
# Exact powers, shifts and bit operations against a slow reference.
proc slowpow {b e} { set r 1; for {set i 0} {$i < $e} {incr i} { set r [expr {$r * $b}] }; return $r }
foreach b {2 3 -7 10 255} { foreach e {0 1 20 40 63 64 65 100} {
  if {[expr {$b ** $e}] != [slowpow $b $e]} { puts "pow $b $e differs" }
} }
foreach x {0 1 -1 12345678901234567890 -98765432109876543210 0x7fffffffffffffff} {
  foreach y {1 3 -3 64 4294967296 -18446744073709551616} {
    puts [list $x $y [expr {$x + $y}] [expr {$x - $y}] [expr {$x * $y}] [expr {$x / $y}] [expr {$x % $y}] [expr {$x & $y}] [expr {$x | $y}] [expr {$x ^ $y}] [expr {$x < $y}] [expr {$x == $y}]]
  }
  puts [list [expr {$x << 70}] [expr {$x >> 3}] [expr {~$x}] [expr {-$x}] [expr {abs($x)}] [expr {double($x)}] [expr {isqrt(abs($x))}] [expr {wide($x)}] [expr {int($x << 40)}]]
}
puts [expr {9223372036854775807 + 1}]
puts [expr {-9223372036854775808 - 1}]
puts [expr {-9223372036854775808 / -1}]
puts [expr {entier(1e20) + 1}]
puts [expr {round(-2.5e19)}]
puts [expr {1e20 == 100000000000000000000}]
puts [expr {2**64 > 1.8446744073709552e19}]
set n 1; for {set i 1} {$i <= 30} {incr i} { set n [expr {$n * $i}] }; puts $n
set x 9223372036854775807; incr x; puts $x; incr x -1; puts $x
dict set d k 9223372036854775807; dict incr d k 2; puts $d
puts [format %llx -255]; puts [format %#llo 4096]; puts [format %hd 70000]; puts [format %hu -1]
puts [format {%.0d|%.0x|%5.3d} 0 0 7]
