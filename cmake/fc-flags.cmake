# The flags of firmware/flags.mk as CMake lists of the same names
# (FC_WARNINGS, FC_LIBRARY_WARNINGS, FC_M4F_CPU, ...).
file(STRINGS "${CMAKE_CURRENT_LIST_DIR}/../firmware/flags.mk" fc_flag_lines REGEX "^FC_[A-Z0-9_]+ :=")
foreach(fc_flag_line IN LISTS fc_flag_lines)
  string(REGEX MATCH "^(FC_[A-Z0-9_]+) := (.*)$" fc_flag_match "${fc_flag_line}")
  separate_arguments(${CMAKE_MATCH_1} UNIX_COMMAND "${CMAKE_MATCH_2}")
endforeach()
