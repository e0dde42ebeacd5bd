proc convert k {
    dict create K $k C [expr {$k - 273.15}] F [expr {$k * 9.0 / 5 - 459.67}] R [expr {$k * 9.0 / 5}]
}
foreach k {0 21 273.15 300 1000} {
    dict for {unit v} [convert $k] { puts -nonewline [format "%s %9.2f  " $unit $v] }
    puts ""
}
