# Layers as folders, enforced by the build (docs/architecture.md).
#
# A source includes another module as "folder/module.h". No directory that holds every folder
# is on any include path: each library gets a directory of its own in the build tree holding a
# single link, <folder> -> the source folder, and exports it. A target therefore resolves
# "folder/x.h" only for its own folder and the folders of the libraries it links, and an
# include of a layer it does not link fails with "No such file or directory".
#
# hl_layer(TARGET FOLDER) makes FOLDER's headers visible to TARGET and to whoever links it.
# A room inside a folder (daemon/core) gets a directory of its own too (layers/daemon_core holding
# daemon/core -> the source folder), so that linking it shows that room and not its siblings.
function(hl_layer target folder)
	string(REPLACE "/" "_" key ${folder})
	set(dir ${CMAKE_BINARY_DIR}/layers/${key})
	get_filename_component(parent ${dir}/${folder} DIRECTORY)
	file(MAKE_DIRECTORY ${parent})
	if(NOT EXISTS ${dir}/${folder})
		file(CREATE_LINK ${CMAKE_SOURCE_DIR}/${folder} ${dir}/${folder} SYMBOLIC)
	endif()
	target_include_directories(${target} PUBLIC ${dir})
endfunction()
