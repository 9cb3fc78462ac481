#pragma once
// Transparent huge pages for big arrays read at random (the database rows a map rebuild copies
// into its archive): with 4 KiB pages nearly every such row costs a TLB miss and a page walk.
#include <cstddef>

namespace qdmeta {

// Asks the kernel to back the whole 2 MiB pages inside [data, data + bytes) with huge pages
// (Linux madvise(MADV_HUGEPAGE); THP's "madvise" mode, Debian's default, needs it). Call it
// before the memory is first touched. A hint only: nothing happens where the system does not
// support it, and the contents and results never depend on it.
void advise_huge_pages(void* data, std::size_t bytes);

}  // namespace qdmeta
