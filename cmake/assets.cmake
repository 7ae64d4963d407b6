# Files compiled into the binary, so that a run needs nothing beside it at run time
# (docs/report.md): the DejaVu Sans font of the preview's text (Debian fonts-dejavu-core) and
# the report page's script, web/src/*.js bundled with three.js by esbuild from the npm lock
# file at build time. The bytes are linked in with the assembler's .incbin.
find_package(PkgConfig REQUIRED)
# Debian libstb-dev: stb_truetype, stb_image(_write)
pkg_check_modules(STB REQUIRED IMPORTED_TARGET stb)
find_file(CMCSURF_FONT_FILE DejaVuSans.ttf
          PATHS /usr/share/fonts/truetype/dejavu /usr/share/fonts/TTF NO_DEFAULT_PATH)
if(NOT CMCSURF_FONT_FILE)
  message(FATAL_ERROR "DejaVuSans.ttf not found: apt-get install fonts-dejavu-core")
endif()

option(CMCSURF_WEB_VIEWER "Bundle the 3D view of report.html (needs npm at build time)" ON)
find_program(CMCSURF_NPM npm)
set(CMCSURF_VIEWER_JS "")
if(CMCSURF_WEB_VIEWER AND CMCSURF_NPM)
  set(web_dir ${CMAKE_BINARY_DIR}/web)
  file(MAKE_DIRECTORY ${web_dir})
  file(GLOB CMCSURF_WEB_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/web/src/*.js)
  # npm ci in the build folder (each build its own node_modules; the lock file pins every byte).
  add_custom_command(
    OUTPUT ${web_dir}/node_modules/.package-lock.json
    COMMAND ${CMAKE_COMMAND} -E copy ${PROJECT_SOURCE_DIR}/web/package.json
            ${PROJECT_SOURCE_DIR}/web/package-lock.json ${web_dir}
    COMMAND ${CMCSURF_NPM} ci --no-audit --no-fund --loglevel=error
    WORKING_DIRECTORY ${web_dir}
    DEPENDS ${PROJECT_SOURCE_DIR}/web/package.json ${PROJECT_SOURCE_DIR}/web/package-lock.json
    COMMENT "npm ci (three.js, esbuild) for report.html")
  set(CMCSURF_VIEWER_JS ${web_dir}/page.min.js)
  add_custom_command(
    OUTPUT ${CMCSURF_VIEWER_JS}
    COMMAND ${CMAKE_COMMAND} -E env NODE_PATH=${web_dir}/node_modules
            ${web_dir}/node_modules/.bin/esbuild ${PROJECT_SOURCE_DIR}/web/src/page.js --bundle
            --minify --format=iife --target=es2020 --legal-comments=none --log-level=warning
            --outfile=${CMCSURF_VIEWER_JS}
    DEPENDS ${web_dir}/node_modules/.package-lock.json ${CMCSURF_WEB_SOURCES}
    COMMENT "esbuild: report page script")
elseif(CMCSURF_WEB_VIEWER)
  message(WARNING "npm not found: report.html is built without its 3D view "
                  "(apt-get install nodejs npm, or -DCMCSURF_WEB_VIEWER=OFF to silence this)")
endif()
if(CMCSURF_VIEWER_JS)
  set(CMCSURF_HAVE_VIEWER 1)
  set(viewer_incbin ${CMCSURF_VIEWER_JS})
else()
  set(CMCSURF_HAVE_VIEWER 0)
  set(viewer_incbin ${CMAKE_BINARY_DIR}/generated/empty.js)
  file(WRITE ${viewer_incbin} "")
endif()
configure_file(${PROJECT_SOURCE_DIR}/cmake/assets.cpp.in ${CMAKE_BINARY_DIR}/generated/assets.cpp
               @ONLY)
set_source_files_properties(${CMAKE_BINARY_DIR}/generated/assets.cpp PROPERTIES
                            OBJECT_DEPENDS "${CMCSURF_FONT_FILE};${viewer_incbin}")
target_sources(cmcsurf_render PRIVATE ${CMAKE_BINARY_DIR}/generated/assets.cpp)
target_link_libraries(cmcsurf_render PRIVATE PkgConfig::STB)
target_link_libraries(cmcsurf_io PRIVATE PkgConfig::STB)  # io/png.cpp
