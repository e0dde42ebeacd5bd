# The shared backdrop of the comparison scenes (wall.inc is POV-Ray's copy).
camera_from 0 0.5 4; camera_target 0 0 0; camera_angle 40; camera_resolution 160 120
ambient_light 0.3 0.3 0.3; trace_depth 10
parallel_light 1 1 1 -1 -1 -2
for {set i 0} {$i < 8} {incr i} {
    for {set j 0} {$j < 8} {incr j} {
        set x0 [expr {-4 + $i}]; set y0 [expr {-4 + $j}]; set x1 [expr {$x0 + 1}]; set y1 [expr {$y0 + 1}]
        if {($i + $j) % 2 == 0} { material 0.9 0.2 0.2 1 0.7 0 1 0 1 } else { material 0.9 0.9 0.9 1 0.7 0 1 0 1 }
        set a [vertex $x0 $y0 -3]; set b [vertex $x1 $y0 -3]; set c [vertex $x1 $y1 -3]; set d [vertex $x0 $y1 -3]
        tri $a $b $c; tri $a $c $d
    }
}
