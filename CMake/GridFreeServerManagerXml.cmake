# Server-manager XML with shared property definitions.
#
# Several GridFree proxies offer the same properties (Walks Per Point, Seed,
# Equation, Source Array ...). Each is written once, in Plugin/Shared/NAME.xml,
# and a proxy includes it with a line
#
#   <!-- shared NAME key="value" ... -->
#
# which is replaced by the fragment with every @key@ replaced by its value
# (@note@, a sentence appended to the property's documentation, may be left
# out). A fragment's line that ends in <!-- unless KEY --> is left out where
# the directive sets KEY (to anything), so that a proxy can offer fewer
# choices of a shared enumeration. ParaView's own XML inheritance (base_proxygroup) would put inherited
# properties, and so their panel groups, above the proxy's own ones; inclusion
# keeps each panel in the order a user fills it in.
function(gridfree_expand_server_manager_xml input output shared_dir)
  file(READ "${input}" text)
  set(depends "${input}")
  string(REGEX MATCHALL "[ ]*<!-- shared [A-Za-z]+[^\n]*-->" directives "${text}")
  foreach(directive IN LISTS directives)
    string(REGEX REPLACE "^[ ]*<!-- shared ([A-Za-z]+).*$" "\\1" name "${directive}")
    set(fragment_file "${shared_dir}/${name}.xml")
    if(NOT EXISTS "${fragment_file}")
      message(FATAL_ERROR "${input}: no shared property ${name} (${fragment_file})")
    endif()
    list(APPEND depends "${fragment_file}")
    file(READ "${fragment_file}" fragment)
    string(REGEX REPLACE "\n$" "" fragment "${fragment}")
    string(REGEX MATCHALL "[A-Za-z]+=\"[^\"]*\"" parameters "${directive}")
    string(REGEX MATCHALL "<!-- unless [A-Za-z]+ -->" conditions "${fragment}")
    foreach(condition IN LISTS conditions)
      string(REGEX REPLACE "^<!-- unless ([A-Za-z]+) -->$" "\\1" key "${condition}")
      if(directive MATCHES " ${key}=\"")
        string(REGEX REPLACE "\n[^\n]*${condition}" "" fragment "${fragment}")
      else()
        string(REPLACE " ${condition}" "" fragment "${fragment}")
      endif()
    endforeach()
    foreach(parameter IN LISTS parameters)
      string(REGEX REPLACE "^([A-Za-z]+)=\".*$" "\\1" key "${parameter}")
      string(REGEX REPLACE "^[A-Za-z]+=\"(.*)\"$" "\\1" value "${parameter}")
      string(REPLACE "@${key}@" "${value}" fragment "${fragment}")
    endforeach()
    # An unused note leaves no empty line in the documentation.
    string(REGEX REPLACE "\n[ ]*@note@" "" fragment "${fragment}")
    if(fragment MATCHES "@[A-Za-z]+@")
      message(FATAL_ERROR "${input}: '${directive}' leaves ${CMAKE_MATCH_0} unset")
    endif()
    string(REPLACE "${directive}" "${fragment}" text "${text}")
  endforeach()
  # Rewritten only when changed, so that the plugin is not rebuilt for nothing.
  file(WRITE "${output}.tmp" "${text}")
  configure_file("${output}.tmp" "${output}" COPYONLY)
  file(REMOVE "${output}.tmp")
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${depends})
endfunction()
