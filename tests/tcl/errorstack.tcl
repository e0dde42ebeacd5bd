# -errorstack and info errorstack (TIP 348), the order of catch's options
# dictionary, and try's -during (issue "Tcl 8.6").
proc f x {g $x$x}
proc g x {error G:$x}
catch {f 12} m o; puts $o
puts [info errorstack]
proc p {} {return -code error x}; catch p m o; puts $o
catch {return -code error y} m o; puts $o
catch {return -code error -errorcode {A B} -level 1 y} m o; puts $o
catch {error z zinfo ZC} m o; puts $o
proc q {} {error z zinfo ZC}; catch q m o; puts $o
catch {return -level 0 -code error -errorstack {A B} w} m o; puts $o
catch {return -level 0 -code error -foo bar w} m o; puts $o
proc u {} { uplevel 1 {error up} }; proc v {} { u }; catch v m o; puts $o
catch {set nosuch} m o; puts $o
catch {lindex} m o; puts $o
proc r {} { lindex }; catch r m o; puts $o
proc t {x} { if {$x} { t [expr {$x-1}] } else { error bottom } }; catch {t 3} m o; puts $o
catch {throw {MY ERR} thrown} m o; puts $o
try { error tr } on error {m o} { puts $o }
catch {try { throw FOO bar } trap {} {em opts} { throw BAR baz }} m o
puts [dict get $o -during]
catch {try { set x 1 } finally { error fin }} m o
puts [dict get $o -during]
catch {try { error a } on error {} { error b } finally { error c }} m o
puts [dict get $o -during]
puts [apply {{} {
    catch {
        try { throw FOO bar } trap {} {em opts} { throw BAR baz }
    } tryem tryopts
    list $opts [dict get $tryopts -during]
}}]
puts [info errorstack]
