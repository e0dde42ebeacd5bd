foreach x {1.0 0.1 0.30000000000000004 1e20 1e-5 1e-4 123456789012345678.0 1e16 1e15 -2.5 3.0e2 .5 5. 1e300 2.2250738585072014e-308 4.9e-324 100.0 0.001 1234.5678} {
    puts [expr {$x + 0.0}]
}
puts [expr {0.1 + 0.2}]; puts [expr {1.0 / 3}]; puts [expr {2.0 / 3}]; puts [expr {10 / 4.0}]
puts [expr {sqrt(2)}]; puts [expr {exp(1)}]; puts [expr {acos(-1)}]; puts [expr {1e308 * 10}]; puts [expr {-1e308 * 10}]
puts [expr {double(7)}]; puts [expr {7 * 1.0}]; puts [expr {1e100}]; puts [expr {-0.0}]; puts [expr {3.14159 * 2}]
set total 0.0; for {set i 0} {$i < 10} {incr i} { set total [expr {$total + 0.1}] }; puts $total
puts [list 1.5 [expr {1.5 * 2}] [expr {1 / 2.0}]]
puts [expr {pow(2, 0.5)}][expr {hypot(3, 4)}][expr {fmod(-7, 3)}][expr {atan2(1, 1)}]
puts [expr {floor(-1.5)}][expr {ceil(-1.5)}][expr {round(1.5)}][expr {int(7.9)}][expr {abs(-2.5)}]
puts [expr {sin(0.5)}][expr {cos(0.5)}][expr {tan(0.5)}][expr {log(10)}][expr {log10(1000)}]
puts [expr {min(3, 1.5, 2)}][expr {max(1, 2, 3)}][expr {wide(3.9)}][expr {entier(-3.9)}]
