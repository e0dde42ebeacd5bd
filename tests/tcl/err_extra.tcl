puts a
puts {b}c
