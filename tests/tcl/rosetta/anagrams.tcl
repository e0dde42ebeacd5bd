set words {listen silent enlist google inlets banana tinsel elgoog apple papel stone tones notes onset}
foreach w $words { dict lappend groups [join [lsort [split $w ""]] ""] $w }
dict for {k ws} $groups { if {[llength $ws] > 1} { puts "$k: [lsort $ws]" } }
