// What a task's own file needs (examples/own-task/arm_task.hpp): the Task interface alone.
#include <qdmeta/core/task.hpp>
