puts start
break
