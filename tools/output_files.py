"""Writing the report's files (report.md, figures/*.png, data/*.csv) without following a symbolic
link someone planted in the experiment directory: each file is written to a temporary file that
O_CREAT | O_EXCL | O_NOFOLLOW creates under a unique name, then renamed over its target (a rename
replaces a link, never writes through it). The folders figures/ and data/ are opened with
O_NOFOLLOW too, and every write goes through their descriptors.
"""
import os
import secrets

from run_files import InputError


class OutputDir:
    """A directory the report writes into, held open so that renaming it or planting links
    cannot redirect the writes."""

    def __init__(self, fd, path):
        self.fd = fd
        self.path = path

    @classmethod
    def open(cls, path):
        """The experiment directory itself (the user's path: a link to it is followed)."""
        try:
            return cls(os.open(path, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC), path)
        except OSError as e:
            raise InputError(f"{path}: cannot open the experiment directory: {e.strerror}") from None

    def subdir(self, name):
        """DIR/name, made if missing; a link or a file there is an error, never followed."""
        path = os.path.join(self.path, name)
        try:
            os.mkdir(name, 0o755, dir_fd=self.fd)
        except FileExistsError:
            pass
        except OSError as e:
            raise InputError(f"{path}: cannot make the folder: {e.strerror}") from None
        try:
            fd = os.open(name, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC, dir_fd=self.fd)
        except OSError as e:
            raise InputError(f"{path}: not a folder the report may write into (a symbolic link or a file?): "
                             f"{e.strerror}") from None
        return OutputDir(fd, path)

    def write(self, name, data):
        """Writes `data` (bytes or str) as DIR/name, replacing whatever is there; returns its path."""
        if isinstance(data, str):
            data = data.encode("utf-8")
        path = os.path.join(self.path, name)
        temp = f".{name}.{os.getpid()}.{secrets.token_hex(8)}.tmp"
        try:
            fd = os.open(temp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o644,
                         dir_fd=self.fd)
        except OSError as e:
            raise InputError(f"{path}: cannot write: {e.strerror}") from None
        try:
            try:
                view = memoryview(data)
                while view:
                    view = view[os.write(fd, view):]
                os.fsync(fd)
            finally:
                os.close(fd)
            os.replace(temp, name, src_dir_fd=self.fd, dst_dir_fd=self.fd)
        except BaseException as e:  # an OSError, or a Ctrl-C: no temporary file is left behind
            try:
                os.unlink(temp, dir_fd=self.fd)
            except OSError:
                pass
            if isinstance(e, OSError):
                raise InputError(f"{path}: cannot write: {e.strerror}") from None
            raise
        return path

    def close(self):
        os.close(self.fd)
