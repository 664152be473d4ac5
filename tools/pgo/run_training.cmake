# Runs the training of profile-guided optimisation when the instrumented trainer is newer than
# the last profile (cmake -P, from the rayfarm_pgo_train step of the top CMakeLists.txt):
#   -DTRAIN=pgo_train -DSOURCE=source tree -DPROFILE=profile directory -DSTAMP=stamp file
# The stamp changes only when the profile does, so the engine is recompiled only then.
if(EXISTS "${STAMP}" AND NOT "${TRAIN}" IS_NEWER_THAN "${STAMP}")
  return()
endif()
file(REMOVE_RECURSE "${PROFILE}")  # counts of an older engine would not match its code
execute_process(COMMAND "${TRAIN}" "${SOURCE}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "profile-guided optimisation: the training run failed (${rc}); configure with -DRAYFARM_PGO=OFF to build without it")
endif()
file(TOUCH "${STAMP}")
