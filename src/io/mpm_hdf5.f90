!> A small HDF5 writer and reader over the HDF5 Fortran API. Every `hdferr` is checked in one
!> place (`check`); after the first failure further calls do nothing and `finish` reports it.
!> A file is written under `<name>.<process id>.part`, created only if no such file exists, and
!> renamed to `<name>` only when complete; a run removes only the partial file it created, so two
!> runs writing one output at once do not destroy each other's files (the last rename wins).
!> A failure's message names the file, the operation and the system's cause (the errno HDF5's file
!> driver recorded: "no space left on device"). HDF5's at-exit clean-up is switched off (open_library):
!> the HDF5 1.10 library frees a file whose close failed (a full disk) but keeps its identifier, and
!> its clean-up at exit closed that freed file again (a segmentation fault in every run that could not
!> write its output). Every file this module opens it also closes, so the clean-up had nothing to do.
!> Not thread-safe (neither is the HDF5 library): call only outside parallel regions.
module mpm_hdf5
   use, intrinsic :: iso_c_binding, only: c_ptr, c_char, c_null_char, c_loc, c_f_pointer, c_associated, c_int
   use hdf5
   use mpm_kinds, only: dp
   use mpm_errors, only: error_t, set_error
   use mpm_files, only: rename_file, remove_file, process_id, register_partial, forget_partial, pause_seconds, &
                        path_kind, path_none, sibling_name
   use mpm_strings, only: str
   implicit none
   private
   !> H5T_VARIABLE of H5Tpublic.h, (size_t)-1: the HDF5 1.10 Fortran API does not export it.
   integer(size_t), parameter :: variable_length = -1_size_t

   interface
      integer(c_int) function c_failure_cause(out, size) bind(C, name='mpm_h5_failure_cause')
         import :: c_int, c_char
         character(kind=c_char), dimension(*), intent(out) :: out
         integer(c_int), value :: size
      end function c_failure_cause
   end interface

   public :: h5_writer_t, h5_read_real, h5_read_int, h5_read_columns, h5_read_attribute_real, h5_read_attribute_int, &
             h5_read_attribute_string, &
             h5_read_string, h5_exists

   type :: h5_writer_t
      integer(hid_t) :: file = -1
      character(len=:), allocatable :: path, part_path
      character(len=:), allocatable :: failure
      !> The system's cause of the failure ("no space left on device"), when HDF5 recorded one.
      character(len=:), allocatable :: cause
      !> Did this writer create part_path (only then may it remove it)?
      logical :: created = .false.
   contains
      procedure :: create => writer_create
      procedure :: group => writer_group
      procedure :: write_real => writer_write_real
      procedure :: write_real_scalar => writer_write_real_scalar
      procedure :: write_int => writer_write_int
      procedure :: write_int_scalar => writer_write_int_scalar
      procedure :: write_strings => writer_write_strings
      procedure :: write_string_scalar => writer_write_string_scalar
      procedure :: attribute_real => writer_attribute_real
      procedure :: attribute_int => writer_attribute_int
      procedure :: attribute_string => writer_attribute_string
      procedure :: attribute_reals => writer_attribute_reals
      procedure :: copy_attributes => writer_copy_attributes
      procedure :: finish => writer_finish
      procedure :: abandon => writer_abandon
      procedure, private :: check => writer_check
      procedure, private :: ok => writer_ok
   end type h5_writer_t

contains

   subroutine writer_create(self, path)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: path
      integer :: hdferr
      logical :: registered
      self%path = trim(path)
      self%part_path = sibling_name(trim(path), '.'//str(process_id())//'.part')
      self%created = .false.
      call open_library(hdferr)
      call self%check(hdferr, 'initialise the HDF5 library')
      call h5eset_auto_f(0, hdferr)
      if (.not. self%ok()) return
      ! register the clean-up first, then create: a signal between the two finds nothing to remove (the
      ! other order left the file behind). A file of that name already there (a dead process's with
      ! the same id) is not registered: the exclusive create fails and it is left alone.
      registered = path_kind(self%part_path) == path_none
      if (registered) call register_partial(self%part_path)
      call h5fcreate_f(self%part_path, H5F_ACC_EXCL_F, self%file, hdferr)
      call self%check(hdferr, "create file '"//self%part_path//"'")
      self%created = hdferr >= 0
      if (registered .and. .not. self%created) then
         ! the create can fail after making the file (its first write on a full disk): the exclusive
         ! create of a name that was free made it this process's, so it is removed
         call remove_file(self%part_path)
         call forget_partial()
      end if
      call test_pause('MPM1D_PAUSE_AFTER_CREATE')
   end subroutine writer_create

   subroutine writer_group(self, name)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer(hid_t) :: group
      integer :: hdferr
      if (.not. self%ok()) return
      call h5gcreate_f(self%file, name, group, hdferr)
      call self%check(hdferr, "create group '"//name//"'")
      if (hdferr == 0) call h5gclose_f(group, hdferr)
   end subroutine writer_group

   !> Create dataset `name` of type `type_id` and shape `dims` (rank 0: scalar); returns its id.
   subroutine open_dataset(self, name, type_id, dims, dset, space)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer(hid_t), intent(in) :: type_id
      integer(hsize_t), intent(in) :: dims(:)
      integer(hid_t), intent(out) :: dset, space
      integer :: hdferr
      dset = -1
      space = -1
      if (.not. self%ok()) return
      if (size(dims) == 0) then
         call h5screate_f(H5S_SCALAR_F, space, hdferr)
      else
         call h5screate_simple_f(size(dims), dims, space, hdferr)
      end if
      call self%check(hdferr, "create dataspace for '"//name//"'")
      if (.not. self%ok()) return
      call h5dcreate_f(self%file, name, type_id, space, dset, hdferr)
      call self%check(hdferr, "create dataset '"//name//"'")
   end subroutine open_dataset

   subroutine close_dataset(self, name, dset, space, hdferr_write)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer(hid_t), intent(in) :: dset, space
      integer, intent(in) :: hdferr_write
      integer :: hdferr
      call self%check(hdferr_write, "write dataset '"//name//"'")
      if (dset >= 0) call h5dclose_f(dset, hdferr)
      if (space >= 0) call h5sclose_f(space, hdferr)
   end subroutine close_dataset

   subroutine writer_write_real(self, name, values)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: values(:)
      integer(hid_t) :: dset, space
      integer(hsize_t) :: dims(1)
      integer :: hdferr
      dims = size(values, kind=hsize_t)
      call open_dataset(self, name, H5T_NATIVE_DOUBLE, dims, dset, space)
      if (.not. self%ok()) return
      call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, values, dims, hdferr)
      call close_dataset(self, name, dset, space, hdferr)
   end subroutine writer_write_real

   subroutine writer_write_real_scalar(self, name, value)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: value
      integer(hid_t) :: dset, space
      integer(hsize_t) :: dims(0)
      integer :: hdferr
      call open_dataset(self, name, H5T_NATIVE_DOUBLE, dims, dset, space)
      if (.not. self%ok()) return
      call h5dwrite_f(dset, H5T_NATIVE_DOUBLE, value, [1_hsize_t], hdferr)
      call close_dataset(self, name, dset, space, hdferr)
   end subroutine writer_write_real_scalar

   subroutine writer_write_int(self, name, values)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer, intent(in) :: values(:)
      integer(hid_t) :: dset, space
      integer(hsize_t) :: dims(1)
      integer :: hdferr
      dims = size(values, kind=hsize_t)
      call open_dataset(self, name, H5T_NATIVE_INTEGER, dims, dset, space)
      if (.not. self%ok()) return
      call h5dwrite_f(dset, H5T_NATIVE_INTEGER, values, dims, hdferr)
      call close_dataset(self, name, dset, space, hdferr)
   end subroutine writer_write_int

   subroutine writer_write_int_scalar(self, name, value)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer, intent(in) :: value
      integer(hid_t) :: dset, space
      integer(hsize_t) :: dims(0)
      integer :: hdferr
      call open_dataset(self, name, H5T_NATIVE_INTEGER, dims, dset, space)
      if (.not. self%ok()) return
      call h5dwrite_f(dset, H5T_NATIVE_INTEGER, value, [1_hsize_t], hdferr)
      call close_dataset(self, name, dset, space, hdferr)
   end subroutine writer_write_int_scalar

   !> A 1-D dataset of strings, each stored trimmed as a variable-length C string (h5dump shows
   !> "completed", not a wall of blanks; h5py reads them as bytes).
   subroutine writer_write_strings(self, name, values)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      character(len=*), intent(in) :: values(:)
      integer(hid_t) :: dset, space, string_type
      integer(hsize_t) :: dims(1)
      character(len=len(values) + 1, kind=c_char), allocatable, target :: texts(:)
      type(c_ptr), allocatable, target :: pointers(:)
      integer :: hdferr, i
      if (.not. self%ok()) return
      call string_type_of(self, string_type)
      allocate (texts(max(size(values), 1)), pointers(max(size(values), 1)))
      do i = 1, size(values)
         texts(i) = trim(values(i))//c_null_char
         pointers(i) = c_loc(texts(i))
      end do
      dims = size(values, kind=hsize_t)
      call open_dataset(self, name, string_type, dims, dset, space)
      if (self%ok()) then
         call h5dwrite_f(dset, string_type, c_loc(pointers), hdferr)
         call close_dataset(self, name, dset, space, hdferr)
      end if
      call h5tclose_f(string_type, hdferr)
   end subroutine writer_write_strings

   !> A scalar string dataset, stored trimmed (variable length).
   subroutine writer_write_string_scalar(self, name, value)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: name, value
      integer(hid_t) :: dset, space, string_type
      integer(hsize_t) :: dims(0)
      character(len=len_trim(value) + 1, kind=c_char), target :: text
      type(c_ptr), target :: pointer
      integer :: hdferr
      if (.not. self%ok()) return
      call string_type_of(self, string_type)
      text = trim(value)//c_null_char
      pointer = c_loc(text)
      call open_dataset(self, name, string_type, dims, dset, space)
      if (self%ok()) then
         call h5dwrite_f(dset, string_type, c_loc(pointer), hdferr)
         call close_dataset(self, name, dset, space, hdferr)
      end if
      call h5tclose_f(string_type, hdferr)
   end subroutine writer_write_string_scalar

   !> The variable-length, null-terminated C string type (file and memory).
   subroutine string_type_of(self, string_type)
      class(h5_writer_t), intent(inout) :: self
      integer(hid_t), intent(out) :: string_type
      integer :: hdferr
      call h5tcopy_f(H5T_C_S1, string_type, hdferr)
      call self%check(hdferr, 'copy the string type')
      call h5tset_size_f(string_type, variable_length, hdferr)
      call self%check(hdferr, 'make the string type variable-length')
   end subroutine string_type_of

   !> Open object `on` (a group or dataset path, '/' for the root) and create a scalar attribute.
   subroutine open_attribute(self, on, name, type_id, object, attr, space)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: on, name
      integer(hid_t), intent(in) :: type_id
      integer(hid_t), intent(out) :: object, attr, space
      integer :: hdferr
      object = -1
      attr = -1
      space = -1
      if (.not. self%ok()) return
      call h5oopen_f(self%file, on, object, hdferr)
      call self%check(hdferr, "open object '"//on//"'")
      if (.not. self%ok()) return
      call h5screate_f(H5S_SCALAR_F, space, hdferr)
      call self%check(hdferr, 'create a scalar dataspace')
      if (.not. self%ok()) return
      call h5acreate_f(object, name, type_id, space, attr, hdferr)
      call self%check(hdferr, "create attribute '"//name//"' on '"//on//"'")
   end subroutine open_attribute

   subroutine close_attribute(self, name, object, attr, space, hdferr_write)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      integer(hid_t), intent(in) :: object, attr, space
      integer, intent(in) :: hdferr_write
      integer :: hdferr
      call self%check(hdferr_write, "write attribute '"//name//"'")
      if (attr >= 0) call h5aclose_f(attr, hdferr)
      if (space >= 0) call h5sclose_f(space, hdferr)
      if (object >= 0) call h5oclose_f(object, hdferr)
   end subroutine close_attribute

   subroutine writer_attribute_real(self, on, name, value)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: on, name
      real(dp), intent(in) :: value
      integer(hid_t) :: object, attr, space
      integer :: hdferr
      call open_attribute(self, on, name, H5T_NATIVE_DOUBLE, object, attr, space)
      hdferr = 0
      if (self%ok()) call h5awrite_f(attr, H5T_NATIVE_DOUBLE, value, [1_hsize_t], hdferr)
      call close_attribute(self, name, object, attr, space, hdferr)
   end subroutine writer_attribute_real

   subroutine writer_attribute_int(self, on, name, value)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: on, name
      integer, intent(in) :: value
      integer(hid_t) :: object, attr, space
      integer :: hdferr
      call open_attribute(self, on, name, H5T_NATIVE_INTEGER, object, attr, space)
      hdferr = 0
      if (self%ok()) call h5awrite_f(attr, H5T_NATIVE_INTEGER, value, [1_hsize_t], hdferr)
      call close_attribute(self, name, object, attr, space, hdferr)
   end subroutine writer_attribute_int

   !> A 1-D real attribute (zero values give an empty one).
   subroutine writer_attribute_reals(self, on, name, values)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: on, name
      real(dp), intent(in) :: values(:)
      integer(hid_t) :: object, attr, space
      integer :: hdferr
      object = -1
      attr = -1
      space = -1
      hdferr = 0
      if (.not. self%ok()) return
      call h5oopen_f(self%file, on, object, hdferr)
      call self%check(hdferr, "open object '"//on//"'")
      if (self%ok()) then
         call h5screate_simple_f(1, [int(size(values), hsize_t)], space, hdferr)
         call self%check(hdferr, 'create a dataspace')
      end if
      if (self%ok()) then
         call h5acreate_f(object, name, H5T_NATIVE_DOUBLE, space, attr, hdferr)
         call self%check(hdferr, "create attribute '"//name//"' on '"//on//"'")
      end if
      hdferr = 0
      if (self%ok() .and. size(values) > 0) &
         call h5awrite_f(attr, H5T_NATIVE_DOUBLE, values, [int(size(values), hsize_t)], hdferr)
      call close_attribute(self, name, object, attr, space, hdferr)
   end subroutine writer_attribute_reals

   subroutine writer_attribute_string(self, on, name, value)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: on, name, value
      integer(hid_t) :: object, attr, space, string_type
      character(len=len_trim(value) + 1, kind=c_char), target :: text
      type(c_ptr), target :: pointer
      integer :: hdferr
      if (.not. self%ok()) return
      call string_type_of(self, string_type)
      text = trim(value)//c_null_char
      pointer = c_loc(text)
      call open_attribute(self, on, name, string_type, object, attr, space)
      hdferr = 0
      if (self%ok()) call h5awrite_f(attr, string_type, c_loc(pointer), hdferr)
      call close_attribute(self, name, object, attr, space, hdferr)
      call h5tclose_f(string_type, hdferr)
   end subroutine writer_attribute_string

   !> Copy the attributes of object `on` of file `source` (scalar reals, integers and strings, 1-D
   !> reals: what this writer writes) to object `on` of this file, through this writer's checked
   !> calls. (HDF5's own copy, H5Ocopy, crashed in its error path when the disk filled during a copy.)
   subroutine writer_copy_attributes(self, source, on)
      class(h5_writer_t), intent(inout) :: self
      character(len=*), intent(in) :: source, on
      integer(hid_t) :: file, object, attr, file_type, space
      integer(hsize_t) :: k
      integer(hssize_t) :: points
      integer :: hdferr, count, class, rank, int_value
      character(len=256) :: name
      character(len=:), allocatable :: text
      real(dp), allocatable :: reals(:)
      if (.not. self%ok()) return
      call h5fopen_f(source, H5F_ACC_RDONLY_F, file, hdferr)
      call self%check(hdferr, "open '"//source//"' to copy the attributes of '"//on//"'")
      if (.not. self%ok()) return
      call h5oopen_f(file, on, object, hdferr)
      call self%check(hdferr, "open '"//on//"' in '"//source//"'")
      count = 0
      if (self%ok()) call h5aget_num_attrs_f(object, count, hdferr)
      do k = 0, count - 1
         if (.not. self%ok()) exit
         call h5aopen_by_idx_f(file, on, H5_INDEX_NAME_F, H5_ITER_INC_F, k, attr, hdferr)
         call self%check(hdferr, "open an attribute of '"//on//"' in '"//source//"'")
         if (.not. self%ok()) exit
         call h5aget_name_f(attr, len(name, size_t), name, hdferr)
         call h5aget_type_f(attr, file_type, hdferr)
         call h5tget_class_f(file_type, class, hdferr)
         call h5tclose_f(file_type, hdferr)
         call h5aget_space_f(attr, space, hdferr)
         call h5sget_simple_extent_ndims_f(space, rank, hdferr)
         call h5sget_simple_extent_npoints_f(space, points, hdferr)
         call h5sclose_f(space, hdferr)
         if (class == H5T_FLOAT_F) then
            allocate (reals(points))
            hdferr = 0
            if (points > 0) call h5aread_f(attr, H5T_NATIVE_DOUBLE, reals, [int(points, hsize_t)], hdferr)
            call self%check(hdferr, "read attribute '"//trim(name)//"' of '"//on//"' in '"//source//"'")
            if (rank == 0) then
               call self%attribute_real(on, trim(name), reals(1))
            else
               call self%attribute_reals(on, trim(name), reals)
            end if
            deallocate (reals)
         else if (class == H5T_INTEGER_F .and. rank == 0) then
            call h5aread_f(attr, H5T_NATIVE_INTEGER, int_value, [1_hsize_t], hdferr)
            call self%check(hdferr, "read attribute '"//trim(name)//"' of '"//on//"' in '"//source//"'")
            call self%attribute_int(on, trim(name), int_value)
         else if (class == H5T_STRING_F .and. rank == 0) then
            call attribute_text(attr, text, hdferr)
            call self%check(hdferr, "read attribute '"//trim(name)//"' of '"//on//"' in '"//source//"'")
            call self%attribute_string(on, trim(name), text)
         else
            call self%check(-1, "copy attribute '"//trim(name)//"' of '"//on//"' in '"//source//"' (not a scalar "// &
                            "real, integer or string, nor a list of reals)")
         end if
         call h5aclose_f(attr, hdferr)
      end do
      call h5oclose_f(object, hdferr)
      call h5fclose_f(file, hdferr)
   end subroutine writer_copy_attributes

   !> Close the file and move it to its final name; on any earlier failure remove the partial file.
   subroutine writer_finish(self, error)
      class(h5_writer_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
      integer :: hdferr
      logical :: renamed
      if (self%file >= 0) then
         call h5fclose_f(self%file, hdferr)
         call self%check(hdferr, "close file '"//self%part_path//"'")
         self%file = -1
      end if
      if (.not. self%ok()) then
         if (self%created) call remove_file(self%part_path)
         call forget_partial()
         if (allocated(self%cause)) then
            call set_error(error, "HDF5 output '"//self%path//"': cannot "//self%failure//": "//self%cause)
         else
            call set_error(error, "HDF5 output '"//self%path//"': cannot "//self%failure)
         end if
         return
      end if
      call crash_hook()
      call rename_file(self%part_path, self%path, renamed)
      if (.not. renamed) then
         if (self%created) call remove_file(self%part_path)
         call set_error(error, "cannot rename '"//self%part_path//"' to '"//self%path//"'")
      end if
      call forget_partial()
   end subroutine writer_finish

   !> Test hook (test_cli_input): with MPM1D_CRASH_BEFORE_RENAME set, the process aborts between the complete
   !> partial file and its rename, as a crash or a kill there would, so that a test can see that nothing
   !> appears under the final name and the partial file keeps the data.
   !> With MPM1D_PAUSE_BEFORE_RENAME=N the process sleeps N seconds there instead, so that a test can
   !> send a signal while the complete partial file exists (test/cli/hostile, class 6).
   subroutine crash_hook()
      integer :: length
      call get_environment_variable('MPM1D_CRASH_BEFORE_RENAME', length=length)
      if (length > 0) then
         call forget_partial() ! a crash, not a signal: the partial file stays
         call abort()
      end if
      call test_pause('MPM1D_PAUSE_BEFORE_RENAME')
   end subroutine crash_hook

   !> Test hook: with the environment variable `name` = N the process sleeps N seconds here, so that a
   !> test can send a signal at this point (MPM1D_PAUSE_AFTER_CREATE: the partial file just created, the
   !> window in which a signal once left it behind; MPM1D_PAUSE_BEFORE_RENAME: the file complete).
   subroutine test_pause(name)
      character(len=*), intent(in) :: name
      integer :: length, seconds, stat
      character(len=16) :: text
      call get_environment_variable(name, text, length=length)
      if (length == 0) return
      read (text, *, iostat=stat) seconds
      if (stat == 0) call pause_seconds(seconds)
   end subroutine test_pause

   !> Close and delete the partial file (nothing appears under the final name).
   subroutine writer_abandon(self)
      class(h5_writer_t), intent(inout) :: self
      integer :: hdferr
      if (self%file >= 0) call h5fclose_f(self%file, hdferr)
      self%file = -1
      if (allocated(self%part_path) .and. self%created) call remove_file(self%part_path)
      if (self%created) call forget_partial()
      self%created = .false.
   end subroutine writer_abandon

   subroutine writer_check(self, hdferr, what)
      class(h5_writer_t), intent(inout) :: self
      integer, intent(in) :: hdferr
      character(len=*), intent(in) :: what
      character(kind=c_char, len=256) :: buffer
      integer :: n
      if (hdferr >= 0) return
      if (.not. allocated(self%failure)) self%failure = what
      ! (a cause recorded by a later failure, the close, serves when the first one recorded none)
      if (allocated(self%cause)) return
      n = c_failure_cause(buffer, int(len(buffer), c_int))
      if (n > 0) self%cause = buffer(1:n)
   end subroutine writer_check

   logical function writer_ok(self)
      class(h5_writer_t), intent(in) :: self
      writer_ok = .not. allocated(self%failure)
   end function writer_ok

   !> Initialise the HDF5 Fortran interface once per process. h5open_f makes a new copy of every
   !> predefined type each time it is called, and HDF5 then walks all of them at every file close:
   !> a merge of N shards that called it at each read took time quadratic in N (200 shards: 2 min).
   !> Nothing here calls h5close_f, so predefined types that exist mean an open interface.
   !> Before it, the library is told not to register its clean-up at exit (see the module's comment).
   subroutine open_library(hdferr)
      integer, intent(out) :: hdferr
      hdferr = 0
      if (H5T_NATIVE_DOUBLE > 0 .and. H5T_NATIVE_INTEGER > 0) return
      call h5dont_atexit_f(hdferr)
      call h5open_f(hdferr)
   end subroutine open_library

   ! ---- reading (tests, merging shard files) ----

   !> Open `path` read-only and dataset `name`; returns ids and the 1-D length (0 for a scalar).
   subroutine open_for_read(path, name, file, dset, length, error)
      character(len=*), intent(in) :: path, name
      integer(hid_t), intent(out) :: file, dset
      integer, intent(out) :: length
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: space
      integer(hsize_t) :: dims(1), maxdims(1)
      integer :: hdferr, rank
      length = 0
      dset = -1
      call open_file_for_read(path, file, error)
      if (allocated(error)) return
      call h5dopen_f(file, name, dset, hdferr)
      if (hdferr < 0) then
         call set_error(error, "no dataset '"//name//"' in '"//path//"'")
         call h5fclose_f(file, hdferr)
         return
      end if
      call h5dget_space_f(dset, space, hdferr)
      call h5sget_simple_extent_ndims_f(space, rank, hdferr)
      if (rank == 1) then
         call h5sget_simple_extent_dims_f(space, dims, maxdims, hdferr)
         length = int(dims(1))
      end if
      call h5sclose_f(space, hdferr)
   end subroutine open_for_read

   subroutine close_read(file, dset)
      integer(hid_t), intent(in) :: file, dset
      integer :: hdferr
      call h5dclose_f(dset, hdferr)
      call h5fclose_f(file, hdferr)
   end subroutine close_read

   !> Read a 1-D (or scalar, as one value) real dataset.
   subroutine h5_read_real(path, name, values, error)
      character(len=*), intent(in) :: path, name
      real(dp), allocatable, intent(out) :: values(:)
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: file, dset
      integer :: length, hdferr
      call open_for_read(path, name, file, dset, length, error)
      if (allocated(error)) return
      allocate (values(max(length, 1)))
      call h5dread_f(dset, H5T_NATIVE_DOUBLE, values, [int(size(values), hsize_t)], hdferr)
      if (hdferr < 0) call set_error(error, "cannot read '"//name//"' from '"//path//"'")
      call close_read(file, dset)
   end subroutine h5_read_real

   !> Read the 1-D real datasets `names` of group `group` of `path`, all of one length n, into the
   !> columns of `columns` (n x size(names)), opening the file once; no columns (0 x size(names)) when
   !> the file has no such group.
   subroutine h5_read_columns(path, group, names, columns, error)
      character(len=*), intent(in) :: path, group
      character(len=*), intent(in) :: names(:)
      real(dp), allocatable, intent(out) :: columns(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: file, dset, space
      integer(hsize_t) :: dims(1), maxdims(1)
      integer :: hdferr, j
      logical :: found
      call open_file_for_read(path, file, error)
      if (allocated(error)) return
      call h5lexists_f(file, group, found, hdferr)
      if (hdferr < 0 .or. .not. found) then
         allocate (columns(0, size(names)))
         call h5fclose_f(file, hdferr)
         return
      end if
      do j = 1, size(names)
         call h5dopen_f(file, group//'/'//trim(names(j)), dset, hdferr)
         if (hdferr < 0) then
            call set_error(error, "no dataset '"//group//'/'//trim(names(j))//"' in '"//path//"'")
            exit
         end if
         call h5dget_space_f(dset, space, hdferr)
         call h5sget_simple_extent_dims_f(space, dims, maxdims, hdferr)
         call h5sclose_f(space, hdferr)
         if (.not. allocated(columns)) allocate (columns(dims(1), size(names)))
         if (dims(1) /= size(columns, 1, kind=hsize_t)) then
            call set_error(error, "the datasets of '"//group//"' in '"//path//"' differ in length")
         else
            call h5dread_f(dset, H5T_NATIVE_DOUBLE, columns(:, j), dims, hdferr)
            if (hdferr < 0) call set_error(error, "cannot read '"//group//'/'//trim(names(j))//"' from '"//path//"'")
         end if
         call h5dclose_f(dset, hdferr)
         if (allocated(error)) exit
      end do
      call h5fclose_f(file, hdferr)
   end subroutine h5_read_columns

   !> Read a 1-D (or scalar, as one value) integer dataset.
   subroutine h5_read_int(path, name, values, error)
      character(len=*), intent(in) :: path, name
      integer, allocatable, intent(out) :: values(:)
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: file, dset
      integer :: length, hdferr
      call open_for_read(path, name, file, dset, length, error)
      if (allocated(error)) return
      allocate (values(max(length, 1)))
      call h5dread_f(dset, H5T_NATIVE_INTEGER, values, [int(size(values), hsize_t)], hdferr)
      if (hdferr < 0) call set_error(error, "cannot read '"//name//"' from '"//path//"'")
      call close_read(file, dset)
   end subroutine h5_read_int

   !> Read a 1-D dataset of strings (variable-length, or fixed-length as older files hold them)
   !> into `values`, each cut to `length` characters.
   subroutine h5_read_string(path, name, length, values, error)
      character(len=*), intent(in) :: path, name
      integer, intent(in) :: length
      character(len=length), allocatable, intent(out) :: values(:)
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: file, dset, string_type, file_type, space
      type(c_ptr), allocatable, target :: pointers(:)
      type(c_ptr) :: buffer
      logical :: variable
      integer :: count, hdferr, i
      call open_for_read(path, name, file, dset, count, error)
      if (allocated(error)) return
      allocate (values(max(count, 1)))
      values = ''
      call h5dget_type_f(dset, file_type, hdferr)
      call h5tis_variable_str_f(file_type, variable, hdferr)
      call h5tclose_f(file_type, hdferr)
      if (variable) then
         call h5tcopy_f(H5T_C_S1, string_type, hdferr)
         call h5tset_size_f(string_type, variable_length, hdferr)
         allocate (pointers(size(values)))
         buffer = c_loc(pointers)
         call h5dread_f(dset, string_type, buffer, hdferr)
         if (hdferr >= 0) then
            do i = 1, size(values)
               values(i) = c_text(pointers(i))
            end do
            call h5dget_space_f(dset, space, hdferr)
            call h5dvlen_reclaim_f(string_type, space, H5P_DEFAULT_F, buffer, hdferr)
            call h5sclose_f(space, hdferr)
         else
            call set_error(error, "cannot read '"//name//"' from '"//path//"'")
         end if
      else
         call h5tcopy_f(H5T_FORTRAN_S1, string_type, hdferr)
         call h5tset_size_f(string_type, int(length, size_t), hdferr)
         call h5dread_f(dset, string_type, values, [int(size(values), hsize_t)], hdferr)
         if (hdferr < 0) call set_error(error, "cannot read '"//name//"' from '"//path//"'")
      end if
      call h5tclose_f(string_type, hdferr)
      call close_read(file, dset)
   end subroutine h5_read_string

   !> The null-terminated C string at `pointer` ('' for a null pointer).
   function c_text(pointer) result(text)
      type(c_ptr), intent(in) :: pointer
      character(len=:), allocatable :: text
      character(kind=c_char), pointer :: chars(:)
      integer :: n
      if (.not. c_associated(pointer)) then
         text = ''
         return
      end if
      call c_f_pointer(pointer, chars, [huge(0)])
      n = 0
      do while (chars(n + 1) /= c_null_char)
         n = n + 1
      end do
      allocate (character(len=n) :: text)
      text = transfer(chars(1:n), text)
   end function c_text

   !> Read a real attribute `name` of object `on` ('/' for the root).
   subroutine h5_read_attribute_real(path, on, name, value, error)
      character(len=*), intent(in) :: path, on, name
      real(dp), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: file, attr
      integer :: hdferr
      value = 0.0_dp
      call open_attribute_for_read(path, on, name, file, attr, error)
      if (allocated(error)) return
      call h5aread_f(attr, H5T_NATIVE_DOUBLE, value, [1_hsize_t], hdferr)
      if (hdferr < 0) call set_error(error, "cannot read attribute '"//name//"' of '"//on//"' in '"//path//"'")
      call h5aclose_f(attr, hdferr)
      call h5fclose_f(file, hdferr)
   end subroutine h5_read_attribute_real

   !> Read an integer attribute `name` of object `on`.
   subroutine h5_read_attribute_int(path, on, name, value, error)
      character(len=*), intent(in) :: path, on, name
      integer, intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: file, attr
      integer :: hdferr
      value = 0
      call open_attribute_for_read(path, on, name, file, attr, error)
      if (allocated(error)) return
      call h5aread_f(attr, H5T_NATIVE_INTEGER, value, [1_hsize_t], hdferr)
      if (hdferr < 0) call set_error(error, "cannot read attribute '"//name//"' of '"//on//"' in '"//path//"'")
      call h5aclose_f(attr, hdferr)
      call h5fclose_f(file, hdferr)
   end subroutine h5_read_attribute_int

   !> Does `path` exist as a readable HDF5 file holding object `name` (with attribute `attribute`)?
   logical function h5_exists(path, name, attribute)
      character(len=*), intent(in) :: path, name
      character(len=*), intent(in), optional :: attribute
      integer(hid_t) :: file
      integer :: hdferr
      logical :: found
      h5_exists = .false.
      call open_library(hdferr)
      call h5eset_auto_f(0, hdferr)
      call h5fopen_f(path, H5F_ACC_RDONLY_F, file, hdferr)
      if (hdferr < 0) return
      call h5lexists_f(file, name, found, hdferr)
      if (hdferr >= 0 .and. found .and. present(attribute)) call h5aexists_by_name_f(file, name, attribute, found, hdferr)
      h5_exists = hdferr >= 0 .and. found
      call h5fclose_f(file, hdferr)
   end function h5_exists

   !> Read a string attribute (variable-length, or fixed-length as older files hold it; up to
   !> `len(value)` characters).
   subroutine h5_read_attribute_string(path, on, name, value, error)
      character(len=*), intent(in) :: path, on, name
      character(len=*), intent(out) :: value
      type(error_t), allocatable, intent(out) :: error
      integer(hid_t) :: file, attr
      character(len=:), allocatable :: text
      integer :: hdferr
      value = ''
      call open_attribute_for_read(path, on, name, file, attr, error)
      if (allocated(error)) return
      call attribute_text(attr, text, hdferr)
      value = text
      if (hdferr < 0) call set_error(error, "cannot read attribute '"//name//"' of '"//on//"' in '"//path//"'")
      call h5aclose_f(attr, hdferr)
      call h5fclose_f(file, hdferr)
   end subroutine h5_read_attribute_string

   !> The text of the open scalar string attribute `attr` (variable-length, or fixed-length as older
   !> files hold it); `hdferr` < 0 when it cannot be read.
   subroutine attribute_text(attr, text, hdferr)
      integer(hid_t), intent(in) :: attr
      character(len=:), allocatable, intent(out) :: text
      integer, intent(out) :: hdferr
      integer(hid_t) :: string_type, space
      integer(size_t) :: length
      type(c_ptr), target :: pointer(1)
      type(c_ptr) :: buffer
      logical :: variable
      integer :: status
      text = ''
      call h5aget_type_f(attr, string_type, hdferr)
      if (hdferr < 0) return
      call h5tis_variable_str_f(string_type, variable, hdferr)
      if (variable) then
         buffer = c_loc(pointer)
         call h5aread_f(attr, string_type, buffer, hdferr)
         if (hdferr >= 0) then
            text = c_text(pointer(1))
            call h5aget_space_f(attr, space, status)
            call h5dvlen_reclaim_f(string_type, space, H5P_DEFAULT_F, buffer, status)
            call h5sclose_f(space, status)
         end if
      else
         call h5tget_size_f(string_type, length, hdferr)
         if (hdferr >= 0) then
            deallocate (text)
            allocate (character(len=length) :: text)
            call h5aread_f(attr, string_type, text, [1_hsize_t], hdferr)
         end if
      end if
      call h5tclose_f(string_type, status)
   end subroutine attribute_text

   !> Open `path` read-only (the library opened first, its error printing off).
   subroutine open_file_for_read(path, file, error)
      character(len=*), intent(in) :: path
      integer(hid_t), intent(out) :: file
      type(error_t), allocatable, intent(out) :: error
      integer :: hdferr
      call open_library(hdferr)
      call h5eset_auto_f(0, hdferr)
      call h5fopen_f(path, H5F_ACC_RDONLY_F, file, hdferr)
      if (hdferr < 0) call set_error(error, "cannot open HDF5 file '"//path//"'")
   end subroutine open_file_for_read

   subroutine open_attribute_for_read(path, on, name, file, attr, error)
      character(len=*), intent(in) :: path, on, name
      integer(hid_t), intent(out) :: file, attr
      type(error_t), allocatable, intent(out) :: error
      integer :: hdferr
      call open_file_for_read(path, file, error)
      if (allocated(error)) return
      call h5aopen_by_name_f(file, on, name, attr, hdferr)
      if (hdferr < 0) then
         call set_error(error, "no attribute '"//name//"' on '"//on//"' in '"//path//"'")
         call h5fclose_f(file, hdferr)
      end if
   end subroutine open_attribute_for_read
end module mpm_hdf5
