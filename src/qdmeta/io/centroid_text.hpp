#pragma once
// CVT centroids a user supplies as text (cvt.centroids_file): one centroid per line, its
// coordinates separated by white space, as the authors' centroid files (and numpy.savetxt) write
// them. Blank lines are skipped.
#include <filesystem>

#include "qdmeta/core/types.hpp"

namespace qdmeta {

// The `count` x `dimensions` centroids in `path`. InputError saying what is wrong, in one line,
// when the file cannot be read, a line is not `dimensions` numbers, a number is not finite or
// lies outside [0, 1] (the base-feature space), or there are not `count` lines.
RowMatrix read_centroid_text(const std::filesystem::path& path, Index count, Index dimensions);

}  // namespace qdmeta
