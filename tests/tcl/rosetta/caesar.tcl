proc caesar {text key} {
    set out ""
    foreach c [split $text ""] {
        if {[string is upper $c]} {
            append out [format %c [expr {([scan $c %c] - 65 + $key) % 26 + 65}]]
        } elseif {[string is lower $c]} {
            append out [format %c [expr {([scan $c %c] - 97 + $key) % 26 + 97}]]
        } else { append out $c }
    }
    return $out
}
set msg "The quick brown fox Jumped over the lazy Dog!"
set enc [caesar $msg 11]
puts $enc
puts [caesar $enc -11]
