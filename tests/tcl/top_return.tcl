puts start
return
puts never
