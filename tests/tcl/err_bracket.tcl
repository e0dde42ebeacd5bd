puts a
puts [list b
