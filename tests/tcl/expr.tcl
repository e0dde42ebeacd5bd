puts [expr {1 + 2 * 3 - 4 / 2}]
puts [expr {2 ** 3 ** 2}][expr {-2 ** 2}][expr {(-2) ** 3}][expr {2 ** -1}][expr {2 ** 0}]
puts [expr {-7 / 2}][expr {7 / -2}][expr {-7 % 2}][expr {7 % -2}][expr {-7 % -2}]
puts [expr {1 << 4}][expr {-16 >> 2}][expr {5 & 3}][expr {5 | 3}][expr {5 ^ 3}][expr {~5}]
puts [expr {!0}][expr {!1}][expr {!2.5}][expr {!"yes"}][expr {!false}]
puts [expr {1 < 2}][expr {2 <= 2}][expr {3 > 4}][expr {3 >= 4}][expr {1 == 1.0}][expr {1 != 2}]
puts [expr {"abc" < "abd"}][expr {"10" < "9"}][expr {"a10" < "a9"}][expr {"abc" == "abc"}][expr {"x" != "y"}]
puts [expr {"3" eq "3.0"}][expr {3 == "3.0"}][expr {"a" ne "b"}][expr {"b" in {a b c}}][expr {"d" ni {a b c}}]
puts [expr {1 && 0}][expr {1 || 0}][expr {0 && [error never]}][expr {1 || [error never]}]
puts [expr {1 ? "yes" : "no"}][expr {0 ? "yes" : "no"}][expr {1 ? 0 ? "a" : "b" : "c"}]
puts [expr {true}][expr {false || on}][expr {yes && no}]
set x 5; set y 2.5; set s "hello"
puts [expr {$x * $y}][expr {$x + [llength {a b c}]}][expr {"$s world"}][expr {[string length $s] * 2}]
puts [expr $x+1][expr "$x * 2"][expr {$x}][expr {"0x10"}][expr {" 7 "}][expr {"1.50"}]
puts [expr 1 + 2 + 3]
puts [expr {0x1F + 0o17 + 0b101 + 010}]
puts [expr {10 % 3}][expr {-10 % 3}][expr {10 / 3}][expr {-10 / 3}]
puts [expr {9223372036854775807}][expr {-9223372036854775807 - 1}]
puts [expr {int(1e10)}][expr {round(-2.5)}][expr {round(2.5)}][expr {round(2.4)}][expr {int(-0.5)}]
puts [expr {srand(42)}]
puts [expr {rand()}][expr {rand()}]
puts [expr {int(rand() * 100)}]
puts [expr {srand(1)}][expr {rand()}]
foreach e {{1 / 0} {1 % 0} {"abc" + 1} {"" * 2} {1.5 % 2} {1.5 << 1} {sqrt(-1)} {0 ** -1} {1 +} {(1 + 2} {1 + 2)} {1 2} {} {nope(1)} {sin()} {sin(1, 2)} {"abc" && 1} {!"abc"} {abc} {08} {$undefined + 1} {1 << -1} {fmod(1, 0)} {acos(2)}} {
    if {[catch {expr $e} m]} { puts "error: $m" } else { puts "ok: $m" }
}
set n 0; while {$n < 5} { incr n }; puts $n
puts [expr {[expr {1 + 1}] + 1}]
