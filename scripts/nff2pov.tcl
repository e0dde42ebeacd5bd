# Writes an NFF scene (Eric Haines' SPD format) as POV-Ray 3.7 scene
# language, for scripts/bench-spd: the same view, background, lights,
# materials and shapes as `nff` reads them (src/shell/nff.rs), so the two
# renderers trace the same scene.
#   - The view: NFF is right-handed, POV-Ray left-handed: `right -x` keeps
#     the picture the same way round.
#   - Lights: the colour, not falling off (our `nff` makes a point light
#     with falloff 1 0 0).
#   - `f r g b Kd Ks Shine T ior`: no ambient, Kd diffuse (over 1 - T, as
#     POV-Ray dims a filtering surface's diffuse light by that), Ks both the
#     Phong highlight and the mirror reflection, T filtered transmission.
#   - Polygons and patches become triangle fans, in one `mesh` per run of
#     polygons under one material (POV-Ray's fastest form for triangles).
#
#   tclsh scripts/nff2pov.tcl in.nff width height > out.pov

lassign $argv in width height
set f [open $in]
foreach line [split [read $f] \n] {
    # `#` starts a comment in NFF.
    set line [lindex [split $line #] 0]
    lappend lines $line
}
close $f

proc vec {x y z} { return "<$x, $y, $z>" }

set out {}
lappend out "global_settings { assumed_gamma 1.0 max_trace_level 5 ambient_light 0 }"
set material none
set mesh {}
set nmat 0

proc flush_mesh {} {
    global mesh out material
    if {[llength $mesh]} {
        lappend out "mesh \{"
        foreach t $mesh { lappend out "  $t" }
        lappend out "  material \{ $material \}\n\}"
        set mesh {}
    }
}

# Every number of the file in one stream, with its item letters.
set tokens [concat {*}$lines]
set i 0
proc tok {} {
    global tokens i
    set w [lindex $tokens $i]
    incr i
    return $w
}
proc tok3 {} { return [vec [tok] [tok] [tok]] }

while {$i < [llength $tokens]} {
    set item [tok]
    switch -- $item {
        v {
            for {set k 0} {$k < 6} {incr k} {
                set key [tok]
                switch -- $key {
                    from { set from [tok3] }
                    at { set at [tok3] }
                    up { set up [tok3] }
                    angle { set angle [tok] }
                    hither { tok }
                    resolution { tok; tok }
                }
            }
            lappend out "camera \{ perspective location $from right -x*$width/$height up y\
                sky $up angle $angle look_at $at \}"
        }
        b { lappend out "background \{ rgb [tok3] \}" }
        l {
            set p [tok3]
            # An optional colour: three more numbers before the next item.
            set colour "<1, 1, 1>"
            set peek [lindex $tokens $i]
            if {[string is double -strict $peek]} { set colour [tok3] }
            lappend out "light_source \{ $p rgb $colour \}"
        }
        f {
            flush_mesh
            set c [list [tok] [tok] [tok]]
            lassign [list [tok] [tok] [tok] [tok] [tok]] kd ks shine t ior
            if {$ior == 0} { set ior 1 }
            incr nmat
            set name M$nmat
            # POV-Ray lights a filtering surface's diffuse term times
            # (1 - filter); ours is Kd whatever T is.
            if {$t > 0 && $t < 1} { set kd [expr {$kd / (1.0 - $t)}] }
            lappend out "#declare $name = material \{ texture \{\
                pigment \{ rgbf <[join $c {, }], $t> \}\
                finish \{ ambient 0 diffuse $kd phong $ks phong_size $shine reflection \{ $ks \} \} \}\
                interior \{ ior $ior \} \}"
            set material $name
        }
        c {
            flush_mesh
            set base [tok3]; set r0 [expr {abs([tok])}]
            set apex [tok3]; set r1 [expr {abs([tok])}]
            if {$r0 == $r1} {
                lappend out "cylinder \{ $base, $apex, $r0 open material \{ $material \} \}"
            } else {
                lappend out "cone \{ $base, $r0, $apex, $r1 open material \{ $material \} \}"
            }
        }
        s {
            flush_mesh
            set c [tok3]
            lappend out "sphere \{ $c, [tok] material \{ $material \} \}"
        }
        p {
            set n [tok]
            set v {}
            for {set k 0} {$k < $n} {incr k} { lappend v [tok3] }
            for {set k 1} {$k < $n - 1} {incr k} {
                lappend mesh "triangle \{ [lindex $v 0], [lindex $v $k], [lindex $v $k+1] \}"
            }
        }
        pp {
            set n [tok]
            set v {}
            for {set k 0} {$k < $n} {incr k} { lappend v "[tok3], [tok3]" }
            for {set k 1} {$k < $n - 1} {incr k} {
                lappend mesh "smooth_triangle \{ [lindex $v 0], [lindex $v $k], [lindex $v $k+1] \}"
            }
        }
        default { error "$in: unknown NFF item \"$item\"" }
    }
}
flush_mesh
puts [join $out \n]
