set text {It was the best of times, it was the worst of times, it was the age of wisdom,
it was the age of foolishness, it was the epoch of belief, it was the epoch of incredulity}
foreach w [regexp -all -inline {[a-z]+} [string tolower $text]] { dict incr freq $w }
foreach {w n} [lsort -stride 2 -index 1 -integer -decreasing [lsort -stride 2 $freq]] { puts [format "%-12s %3d" $w $n] }
