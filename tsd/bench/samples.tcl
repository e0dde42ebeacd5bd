# The cost of a sample (issue "sampling"): tsd/spheres.tsd (reflection,
# refraction, three kinds of light) at 320x240, traced with 1 camera ray per
# pixel and with 16, best of three each, in turn, in one process. Prints
# the times, the ratio (16 means nothing on top of the rays), and Mrays/s.
# Run by scripts/bench; not a sample scene (its name is not .tsd).
set here [file dirname [info script]]
source [file join $here .. spheres.tsd]
camera_resolution 320 240
set out /tmp/rayshell-bench-samples.ppm
proc best {n} {
    global out
    samples $n
    set b 1e99
    for {set i 0} {$i < 3} {incr i} {
        # A scene command, so the picture is traced again, not reused.
        seed $i
        set t [lindex [time {render $out}] 0]
        if {$t < $b} { set b $t }
    }
    set m 0
    foreach line [split [stats] \n] {
        if {[string match "speed *" $line]} { set m [lindex $line 1] }
    }
    return [list [expr {$b / 1e3}] $m]
}
lassign [best 1] t1 m1
lassign [best 16] t16 m16
puts [format "samples 1: %.1f ms (%.2f Mrays/s); samples 16: %.1f ms (%.2f Mrays/s); 16 samples cost %.2fx one (16 is nothing on top)" \
    $t1 $m1 $t16 $m16 [expr {$t16 / $t1}]]
