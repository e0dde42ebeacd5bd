# A stand-in for tcltest (issue "Tcl 8.6"), loaded the same way by tclsh and
# raytrace, so both run Tcl's own test files under one harness. It does not
# judge: each test's return code and result are printed as a record line,
# and scripts/tcltest/compare.tcl compares raytrace's records with tclsh's.
#
#   tclsh|raytrace scripts/tcltest/lite.tcl FILE.test
#
# Records (one line each, prefixed by \x01 so test output cannot pass for
# one): CASE name code result; SKIP name constraints; ABORT message (the
# file stopped early). Newlines and backslashes in results are escaped.
# The harness uses only the commands raytrace had before it ran the suite.

# The test files begin with
#     if {"::tcltest" ni [namespace children]} { package require tcltest; ... }
# so ::tcltest must seem to exist already.
if {[llength [info commands namespace]]} {
    namespace eval ::tcltest {}
} else {
    proc namespace {sub args} {
        if {$sub eq "children"} { return ::tcltest }
        error "namespace $sub: not available"
    }
}

set ::lite_seen() 0
proc lite_escape {s} { string map [list \\ \\\\ \n \\n \r \\r] $s }
proc lite_name {name} {
    # Tests in loops repeat names: number the repeats.
    if {[info exists ::lite_seen($name)]} {
        incr ::lite_seen($name)
        return "$name#$::lite_seen($name)"
    }
    set ::lite_seen($name) 0
    return $name
}

# The constraints both interpreters get: a Unix machine, no C test commands
# (testobj, testevalex... are undefined, so false, as tcltest leaves them).
foreach {c v} {
    unix 1 win 0 mac 0 unixOrWin 1 macOrWin 0 macOrUnix 1 tempNotWin 1 tempNotMac 1
    unixOnly 1 winOnly 0 nonPortable 0 knownBug 0 notRoot 1 root 0 interactive 0
    nonBlockFiles 1 asyncPipeClose 1 unixExecs 1 eformat 1 stdio 1 singleTestInterp 1
    emptyTest 0 userInteraction 0 unixCrash 0 winCrash 0 wideIs64bit 1 wideBiggerThanInt 1
    longIs64bit 1 intIs32bit 1 pointerIs64bit 1 ieeeFloatingPoint 1 bigEndian 0 littleEndian 1
    memory 0 knownMsvcBug 0 fullutf 1 utf16 0 ucs2 0 tip389 0 debug 0 largefileSupport 1
    interpreter 1
} { set ::lite_constraint($c) $v }

proc testConstraint {c args} {
    if {[llength $args]} { set ::lite_constraint($c) [lindex $args 0] }
    if {[info exists ::lite_constraint($c)]} { return $::lite_constraint($c) }
    return 0
}
proc lite_ok {constraints} {
    foreach c $constraints {
        # A constraint may be an expression of constraints ("unix || win").
        if {[regexp_free $c]} {
            if {![testConstraint $c]} { return 0 }
        } else {
            return 0
        }
    }
    return 1
}
# A plain constraint name (letters, digits, _ and an optional leading !).
proc regexp_free {c} {
    set c [string trimleft $c !]
    string is wordchar -strict $c
}

proc test {name description args} {
    set name [lite_name $name]
    set o(-constraints) {}
    set o(-setup) {}
    set o(-body) {}
    set o(-cleanup) {}
    if {[llength $args] && [string index [lindex $args 0] 0] eq "-"} {
        foreach {k v} $args { set o($k) $v }
    } else {
        switch [llength $args] {
            2 { set o(-body) [lindex $args 0] }
            3 { set o(-constraints) [lindex $args 0]; set o(-body) [lindex $args 1] }
            default { puts "\x01CASE [lite_escape $name] BADARGS {}"; return }
        }
    }
    set cons $o(-constraints)
    set neg {}
    foreach c $cons {
        if {[string index $c 0] eq "!"} {
            if {[testConstraint [string range $c 1 end]]} { set neg $c }
        } elseif {![lite_ok [list $c]]} {
            set neg $c
        }
    }
    if {$neg ne ""} {
        puts "\x01SKIP [lite_escape $name] [lite_escape $cons]"
        return
    }
    catch {uplevel 1 $o(-setup)}
    set code [catch {uplevel 1 $o(-body)} result]
    catch {uplevel 1 $o(-cleanup)}
    puts "\x01CASE [lite_escape $name] $code [lite_escape $result]"
}

# The rest of tcltest's commands the files call at their top level.
proc cleanupTests {args} {}
proc loadTestedCommands {args} {}
proc configure {args} {}
proc customMatch {args} {}
proc interpreter {args} { info nameofexecutable }
proc temporaryDirectory {args} { return /tmp }
proc workingDirectory {args} { pwd }
proc makeFile {contents name {dir /tmp}} { return [file join $dir $name] }
proc removeFile {args} {}
proc makeDirectory {name {dir /tmp}} { return [file join $dir $name] }
proc removeDirectory {args} {}
proc viewFile {args} { return "" }
proc bytestring {s} { return $s }
proc testsDirectory {} { file dirname $::lite_file }

# Also by their qualified names (`::tcltest::cleanupTests`).
foreach p {test testConstraint cleanupTests loadTestedCommands configure customMatch
        interpreter temporaryDirectory workingDirectory makeFile removeFile makeDirectory
        removeDirectory viewFile bytestring testsDirectory} {
    proc ::tcltest::$p args "uplevel 1 \[list $p\] \$args"
}

set ::lite_file [lindex $argv 0]
if {[catch {source $::lite_file} message]} {
    puts "\x01ABORT [lite_escape $message]"
}
