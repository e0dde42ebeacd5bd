# A stand-in for tclbench's libbench.tcl, run the same way by tclsh and
# raytrace: each `bench` runs its -pre script, its -body once (to compile
# it), then times the body with `time` and prints one line,
# "description<TAB>microseconds per iteration" (or "ERROR <message>").
#   tclsh libbench.tcl FILE.bench ITERATIONS
set BENCH(ITERS) [lindex $argv 1]
proc bench {args} {
    global BENCH
    array set opts {-pre {} -body {} -desc {} -post {}}
    set opts(-iter) $BENCH(ITERS)
    foreach {key val} $args {
        switch -glob -- $key {
            -auto* - -res* {}
            -pr* { set opts(-pre) $val }
            -po* { set opts(-post) $val }
            -bo* { set opts(-body) $val }
            -de* { set opts(-desc) $val }
            -it* { if {$opts(-iter) > $val} { set opts(-iter) $val } }
            default { error "unknown option $key" }
        }
    }
    if {$opts(-pre) ne ""} { uplevel #0 $opts(-pre) }
    if {$opts(-body) ne ""} {
        if {[catch {uplevel #0 $opts(-body)} res]} {
            puts "$opts(-desc)\tERROR [string map {\n { }} $res]"
        } else {
            set t [lindex [time {uplevel #0 $opts(-body)} $opts(-iter)] 0]
            puts "$opts(-desc)\t$t"
        }
    }
    if {$opts(-post) ne ""} { uplevel #0 $opts(-post) }
}
cd [file dirname [lindex $argv 0]]
source [file tail [lindex $argv 0]]
