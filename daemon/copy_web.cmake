# Copies the web UI (daemon/web/) to the build tree; an absent or empty source gives an empty dir.
file(REMOVE_RECURSE "${DST}")
file(MAKE_DIRECTORY "${DST}")
if(EXISTS "${SRC}")
  file(COPY "${SRC}/" DESTINATION "${DST}")
endif()
