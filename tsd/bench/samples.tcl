# The cost of a sample (issue "sampling"): tsd/spheres.tsd (reflection,
# refraction, three kinds of light) at 320x240, traced with 1 camera ray per
# pixel and with 16, best of three each, in turn, in one process. Prints
# the times, the ratio (16 means nothing on top of the rays), and Mrays/s.
# Then the rate of area-light shadow rays (below).
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

# Area-light shadow rays, which go through the any-hit path: the teapot
# (tsd/teapot.tsd, 6,320 triangles) at 320x240 lit by one point light, then
# by a 1 x 1 area light of the same power in its place, 4 x 4 shadow
# samples per hit. The extra time over the extra shadow rays is the cost of
# one: printed as a rate, and against the time per camera ray (with its
# shading and its shadow ray) of the first render.
rename point_light real_point_light
rename parallel_light real_parallel_light
proc point_light args {}
proc parallel_light args {}
proc teapot {light} {
    global here out
    clear_scene
    source [file join $here .. teapot.tsd]
    camera_resolution 320 240
    eval $light
    set b 1e99
    for {set i 0} {$i < 3} {incr i} {
        seed $i
        set t [lindex [time {render $out}] 0]
        if {$t < $b} { set b $t }
    }
    foreach line [split [stats] \n] {
        if {[string match "rays *" $line]} {
            return [list [expr {$b / 1e6}] [lindex $line 1] [lindex $line 3]]
        }
    }
}
# Intensity I = L·A/π for a light of radiance L and area A.
lassign [teapot {real_point_light 40 38 34  -4 8 6}] tp np sp
lassign [teapot {area_light 125.7 119.4 106.8  -4.5 8 5.5  1 0 0  0 0 1  4}] ta na sa
set extra [expr {$sa - $sp}]
set each [expr {($ta - $tp) / $extra}]
puts [format "area light (teapot 320x240): %d shadow rays in %.1f ms, against %d in %.1f ms with a point light: %.2f M area-light shadow rays/s, each %.2fx the time of a camera ray" \
    $sa [expr {$ta * 1e3}] $sp [expr {$tp * 1e3}] [expr {1e-6 / $each}] [expr {$each / ($tp / $np)}]]
