# Writes the man page rayfarm(1) from the same text as --help: `rayfarm --help`, then each
# `rayfarm COMMAND --help`, verbatim, under a section per command. Run at build time by
# cmake/packaging.cmake:  cmake -DRAYFARM=bin/rayfarm -DVERSION=0.1 -DOUT=rayfarm.1 -DVIEW=1 -P make_man.cmake
# VIEW: whether this rayfarm has the viewer (built with Qt 6); without it `view --help` is an
# error, and the page says the command is not in this build instead.
set(ENV{QT_QPA_PLATFORM} offscreen)  # view --help needs no display
function(help_of out)
  execute_process(COMMAND ${RAYFARM} ${ARGN} --help OUTPUT_VARIABLE text ERROR_VARIABLE err RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "make_man: rayfarm ${ARGN} --help exited ${rc}: ${err}")
  endif()
  # roff: a backslash is an escape, and a line starting with . or ' a request.
  string(REPLACE "\\" "\\e" text "${text}")
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

help_of(top)
set(page ".TH RAYFARM 1 \"\" \"rayfarm ${VERSION}\" \"User Commands\"\n")
string(APPEND page ".SH NAME\nrayfarm \\- ray tracer and MPI render farm: glTF models and scene files to turntable films\n")
string(APPEND page ".SH SYNOPSIS\n.B rayfarm\n.I COMMAND\n[options]\n.br\n.B mpirun\n\\-np\n.I N\n.B rayfarm render\n.I MODEL\n\\-o\n.I out.mp4\n")
string(APPEND page ".SH DESCRIPTION\nThe text of\n.BR \"rayfarm \\-\\-help\" ,\nthen of each command's\n.BR \\-\\-help .\nThe whole reference: share/doc/rayfarm/cli.md and farm.md under the install prefix (/usr from the .deb).\n.PP\n.nf\n${top}.fi\n")
foreach(cmd render still view report info)
  if(cmd STREQUAL "view" AND NOT VIEW)
    set(text "Not in this build: rayfarm was built without Qt 6 (Debian: qt6-base-dev), so it has no viewer.\n")
  else()
    help_of(text ${cmd})
  endif()
  string(TOUPPER ${cmd} CMD)
  string(APPEND page ".SH \"RAYFARM ${CMD}\"\n.nf\n${text}.fi\n")
endforeach()
string(APPEND page ".SH \"EXIT STATUS\"\n0 done; 1 a failure other than bad input; 2 bad input or usage (one line, \"rayfarm: error: ...\"); 130, 143, 129, 141 after SIGINT, SIGTERM, SIGHUP, a closed stderr.\n")
string(APPEND page ".SH \"SEE ALSO\"\n.BR mpirun (1)\n")
file(WRITE ${OUT} "${page}")
