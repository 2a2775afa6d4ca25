# Writes the lab's tables into a copy of a documentation page (never into the page itself) and
# fails unless every marked table was written (the script fails on a missing source) and the
# page has at least one. scripts/bench.sh writes the run's machine table; a smoke run gets a
# stand-in that says it is one.
if(NOT EXISTS "${OUTPUT}/machine.md")
  file(WRITE "${OUTPUT}/machine.md"
    "| measured (UTC) | CPU | cores | memory | load average at the start | commit |\n"
    "|---|---|---:|---:|---|---|\n| a CTest smoke run, not a measurement | | | | | |\n")
endif()
file(COPY_FILE "${PAGE}" "${COPY}")
execute_process(COMMAND "${PYTHON}" "${SCRIPT}" "${OUTPUT}" "${COPY}"
  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("${out}${err}")
if(NOT status EQUAL 0)
  message(FATAL_ERROR "update_docs_tables.py failed (${status})")
endif()
if(out MATCHES ": 0 tables written")
  message(FATAL_ERROR "${PAGE} marks no generated table")
endif()
