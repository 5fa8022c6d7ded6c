# cmake -DTOOL=path -DIN=NAME.1.in -DOUT=NAME.1 -P manpage.cmake
# Joins the SYNOPSIS and OPTIONS that `TOOL --help-man` prints (from its
# CLI11 definitions) with the hand-written page IN: they replace IN's lines
# "@SYNOPSIS@" and "@OPTIONS@", and each note of IN,
#   .\" @NOTE --name@
#   more text on the option --name
#   .\" @END@
# goes to the end of that option's entry (a note for an option the tool does
# not have is an error, so notes cannot go stale).
cmake_minimum_required(VERSION 3.18)
execute_process(COMMAND ${TOOL} --help-man OUTPUT_VARIABLE generated RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${TOOL} --help-man: exit status ${rc}")
endif()
set(options_marker ".\\\" @OPTIONS@\n")
string(FIND "${generated}" "${options_marker}" cut)
if(cut EQUAL -1)
  message(FATAL_ERROR "${TOOL} --help-man: no OPTIONS")
endif()
string(SUBSTRING "${generated}" 0 ${cut} synopsis)
string(SUBSTRING "${generated}" ${cut} -1 options)

file(READ ${IN} page)
set(note_start ".\\\" @NOTE ")
set(note_end ".\\\" @END@\n")
while(TRUE)
  string(FIND "${page}" "${note_start}" begin)
  if(begin EQUAL -1)
    break()
  endif()
  string(SUBSTRING "${page}" ${begin} -1 rest)
  string(FIND "${rest}" "\n" key_end)
  string(SUBSTRING "${rest}" 0 ${key_end} key_line)  # .\" @NOTE --name@
  string(FIND "${rest}" "${note_end}" end)
  if(end EQUAL -1)
    message(FATAL_ERROR "${IN}: ${key_line} has no .\\\" @END@")
  endif()
  math(EXPR body_begin "${key_end} + 1")
  math(EXPR body_length "${end} - ${body_begin}")
  string(SUBSTRING "${rest}" ${body_begin} ${body_length} body)
  string(FIND "${options}" "${key_line}\n" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${IN}: ${key_line}: the tool has no such option")
  endif()
  string(REPLACE "${key_line}\n" "${body}" options "${options}")
  string(LENGTH "${note_end}" end_length)
  math(EXPR block_length "${end} + ${end_length}")
  string(SUBSTRING "${page}" 0 ${begin} before)
  math(EXPR after_begin "${begin} + ${block_length}")
  string(SUBSTRING "${page}" ${after_begin} -1 after)
  set(page "${before}${after}")
endwhile()
# The placeholders of options without a note, and the markers, go.
string(REGEX REPLACE "\\.\\\\\" @[A-Z]+[^\n]*\n" "" synopsis "${synopsis}")
string(REGEX REPLACE "\\.\\\\\" @[A-Z]+[^\n]*\n" "" options "${options}")

foreach(marker SYNOPSIS OPTIONS)
  string(FIND "${page}" "\n@${marker}@\n" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${IN}: no line @${marker}@")
  endif()
endforeach()
string(REPLACE "\n@SYNOPSIS@\n" "\n${synopsis}" page "${page}")
string(REPLACE "\n@OPTIONS@\n" "\n${options}" page "${page}")
file(WRITE ${OUT}.tmp "${page}")
file(RENAME ${OUT}.tmp ${OUT})
