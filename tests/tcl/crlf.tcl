# Script files with CRLF (or CR) line ends read as Tcl reads them.
set a 1
puts [list $a \
  2]
proc p {x} {
    return [expr {$x * 2}]
}
puts [p 21]
puts $tcl_interactive
