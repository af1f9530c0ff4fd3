# Compiler warnings for project targets: tetfsi_set_warnings(target)
function(tetfsi_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wno-unused-parameter)
endfunction()
