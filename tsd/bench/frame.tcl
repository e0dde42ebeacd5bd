# The benchmark camera (the same as scripts/embree_bench.c): look at the
# centre of the scene's bounding box from direction (0.25, 0.2, 1), at the
# distance where its bounding sphere fills a 45 degree field of view.
proc frame_scene {{width 1024} {height 1024}} {
    lassign [scene_bounds] x0 y0 z0 x1 y1 z1
    set cx [expr {($x0 + $x1) / 2.0}]; set cy [expr {($y0 + $y1) / 2.0}]; set cz [expr {($z0 + $z1) / 2.0}]
    set r [expr {0.5 * sqrt(($x1 - $x0)**2 + ($y1 - $y0)**2 + ($z1 - $z0)**2)}]
    set d [expr {$r / sin(22.5 * acos(-1) / 180)}]
    set n [expr {sqrt(0.25**2 + 0.2**2 + 1)}]
    camera_from [expr {$cx + $d * 0.25 / $n}] [expr {$cy + $d * 0.2 / $n}] [expr {$cz + $d / $n}]
    camera_target $cx $cy $cz
    camera_up 0 1 0
    camera_angle 45
    camera_resolution $width $height
    # A light above and in front, for the shadow rays.
    point_light 1 1 1 [expr {$cx + $d}] [expr {$cy + 2 * $d}] [expr {$cz + $d}]
}
