# Runs Tcl test files through tclsh and raytrace under scripts/tcltest/lite.tcl
# and compares them case by case (issue "Tcl 8.6"). Run by scripts/tcltests.
#
#   tclsh compare.tcl RAYTRACE TESTSDIR FILE...
#
# For each file: the cases tclsh ran (its skips are excluded, as tcltest's
# constraints exclude them), how many raytrace ran with the same return
# code and result ("agree"), and the share. A file raytrace abandons early
# counts its missing cases as disagreeing. Prints a Markdown table, then
# the total; with -v, each disagreement.

set verbose 0
if {[lindex $argv 0] eq "-v"} { set verbose 1; set argv [lrange $argv 1 end] }
lassign $argv raytrace testsdir
set files [lrange $argv 2 end]
set lite [file join [file dirname [info script]] lite.tcl]

proc records {cmd} {
    # Each run gets 120 s; a hang counts as what it printed so far.
    set out ""
    catch {set out [exec timeout 120 {*}$cmd 2>/dev/null]} out
    set cases {}
    set abort ""
    foreach line [split $out \n] {
        if {[string index $line 0] ne "\x01"} continue
        set line [string range $line 1 end]
        set kind [lindex [split $line " "] 0]
        switch -- $kind {
            CASE {
                regexp {^CASE (\S+) (\S+) (.*)$} $line -> name code result
                dict set cases $name [list $code $result]
            }
            ABORT { set abort [string range $line 6 end] }
        }
    }
    list $cases $abort
}

set total_cases 0
set total_agree 0
puts "| file | cases | agree | share |"
puts "| --- | ---: | ---: | ---: |"
foreach f $files {
    set path [file join $testsdir $f.test]
    lassign [records [list tclsh $lite $path]] want abort_t
    lassign [records [list $raytrace $lite -- $path]] got abort_r
    set n [dict size $want]
    set agree 0
    dict for {name r} $want {
        if {[dict exists $got $name] && [dict get $got $name] eq $r} {
            incr agree
        } elseif {$verbose} {
            set g [expr {[dict exists $got $name] ? [dict get $got $name] : "(not run)"}]
            puts stderr "$f $name\n  tclsh:    [string range $r 0 300]\n  raytrace: [string range $g 0 300]"
        }
    }
    if {$verbose && $abort_r ne ""} { puts stderr "$f: raytrace stopped: $abort_r" }
    incr total_cases $n
    incr total_agree $agree
    set share [expr {$n ? 100.0 * $agree / $n : 100.0}]
    puts [format "| %s | %d | %d | %.0f%% |" $f $n $agree $share]
}
puts [format "| **all** | %d | %d | %.1f%% |" $total_cases $total_agree \
    [expr {$total_cases ? 100.0 * $total_agree / $total_cases : 100.0}]]
