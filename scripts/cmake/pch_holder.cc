// The one source of the precompiled-header holders (scripts/cmake/precompiled_headers.cmake):
// a library needs a file to compile its header with.
