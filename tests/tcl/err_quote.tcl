puts a
puts "b
