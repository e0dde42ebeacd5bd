puts start
error "custom failure"
