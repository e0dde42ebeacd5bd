# Instancing (issue "shapes"): the Stanford bunny (69,451 triangles, one
# BVH) placed once, then a million times in a 1000 x 1000 grid, each a
# `transform { translate ...; instance bunny }`. Prints the geometry and
# BVH memory of both and what one instance adds, and the build and render
# times at 512x288. Run by scripts/bench; not a sample scene.
set here [file dirname [info script]]
proc field {name} {
    foreach line [split [stats] \n] {
        if {[lindex $line 0] eq $name} { return $line }
    }
}
proc place {n} {
    global here
    clear_scene
    camera_from 0 40 120; camera_target 0 0 0; camera_resolution 512 288
    ambient_light 0.3 0.3 0.3; parallel_light 0.8 0.8 0.8 -0.4 -1 -0.6
    group bunny {
        material 0.9 0.85 0.75 0.3 0.7 0 1 0 1
        mesh [file join $here .. models stanford-bunny.obj.gz] -scale 6
    }
    for {set i 0} {$i < $n} {incr i} {
        for {set j 0} {$j < $n} {incr j} {
            transform { translate [expr {($i - $n / 2) * 1.5}] 0 [expr {($j - $n) * 1.5}]; instance bunny }
        }
    }
    render /tmp/rayshell-bench-instances.ppm
    # "memory     geometry + BVH 5.4 MiB; ..." and "bvh build  0.38 s ..."
    list [lindex [field memory] 4] [lindex [field bvh] 2] [lindex [field render] 1]
}
lassign [place 1] one build1 render1
lassign [place 1000] million build render
puts [format "instances: one bunny %.1f MiB of geometry and BVH; a million instances %.1f MiB, %.0f bytes each; build %.2f s, render %.3f s at 512x288" \
    $one $million [expr {($million - $one) * 1048576 / 999999.0}] $build $render]
