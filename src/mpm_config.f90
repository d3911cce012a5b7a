!> Namelist configuration of one run: read, validate (reporting every problem), resolve derived
!> quantities (wave speed, element size, time step, step count) and echo.
module mpm_config
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use mpm_kinds, only: dp, i8, pi
   use mpm_errors, only: error_t, set_error, append_error
   use mpm_strings, only: str, lower
   use mpm_files, only: available_memory
   use mpm_particles, only: bytes_per_particle
   implicit none
   private
   public :: config_t, read_config, validate_config, resolve_config, write_config_namelist, config_namelist
   public :: default_config, config_summary, known_schemes, is_known_scheme
   public :: max_snapshots, unset, scan_groups, read_group_error, check_output_path, group_text
   public :: step_count, stability_limit

   character(len=*), parameter :: identifier_characters = &
                                  'abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_'
   !> Sentinel for "not given" reals; no physical input takes this value.
   real(dp), parameter :: unset = -huge(1.0_dp)
   !> Most snapshot times one run accepts.
   integer, parameter :: max_snapshots = 64
   !> Schemes the code implements.
   character(len=*), parameter :: known_schemes = 'usf, usl, musl'
   !> Largest number of particles or elements one run accepts (array indices are default integers).
   integer(i8), parameter :: max_count = int(huge(1), i8)
   !> Time-step fraction above which a run is refused outright (far beyond any stability limit).
   real(dp), parameter :: max_dt_fraction = 10.0_dp

   !> Everything one run needs to know; defaults are the paper's Table 1 and its verification case.
   type :: config_t
      ! &scene
      character(len=32) :: scene_kind = 'vibrating_bar'
      real(dp) :: length = 25.0_dp
      real(dp) :: youngs_modulus = 200.0e9_dp
      real(dp) :: density = 7800.0_dp
      real(dp) :: velocity_amplitude = 0.1_dp
      integer :: mode = 1
      ! &discretisation
      character(len=8) :: scheme = 'usl'
      integer :: elements = 20
      integer :: particles_per_element = 1
      real(dp) :: dt_fraction = 0.1_dp
      !> Empty grid cells beyond each free end of the body; -1: the scene's expected motion + 2 cells.
      integer :: margin_cells = -1
      !> 'auto': the fused linear kernels where they apply, else the generic path; 'generic': always generic.
      character(len=8) :: kernels = 'auto'
      ! &run
      real(dp) :: periods = 2.0_dp
      real(dp) :: end_time = unset
      ! &output
      character(len=1024) :: file = 'bar.h5'
      logical :: history = .true.
      integer :: snapshot_count = 0
      real(dp) :: snapshot_times(max_snapshots) = 0.0_dp
      ! &guards
      !> A run fails when its total energy exceeds this factor times the initial energy.
      real(dp) :: energy_growth_limit = 10.0_dp
      !> A run fails when a particle moves more than this many cells in one step.
      real(dp) :: max_cell_move = 1.0_dp
      ! resolved (derived) quantities, filled by resolve_config
      real(dp) :: wave_speed = 0.0_dp
      real(dp) :: dx = 0.0_dp
      real(dp) :: dt = 0.0_dp
      real(dp) :: period = 0.0_dp
      real(dp) :: final_time = 0.0_dp
      integer :: steps = 0
   end type config_t

contains

   !> The built-in default: the paper's verification case (20 elements, 1 particle per element,
   !> 10% of the critical step, USL, two periods of the first mode).
   function default_config() result(config)
      type(config_t) :: config
      config = config_t()
      call resolve_config(config)
   end function default_config

   logical function is_known_scheme(scheme)
      character(len=*), intent(in) :: scheme
      select case (trim(scheme))
      case ('usf', 'usl', 'musl')
         is_known_scheme = .true.
      case default
         is_known_scheme = .false.
      end select
   end function is_known_scheme

   !> Read `path`: groups &scene, &discretisation, &run, &output, all optional.
   !> `extra_groups` names further groups another reader handles (e.g. 'sweep'),
   !> so that they are not reported as unknown. On any problem `error` lists them all.
   subroutine read_config(path, config, error, extra_groups)
      character(len=*), intent(in) :: path
      type(config_t), intent(out) :: config
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in), optional :: extra_groups(:)

      character(len=32) :: kind
      real(dp) :: length, youngs_modulus, density, velocity_amplitude
      integer :: mode
      character(len=32) :: scheme
      integer :: elements, particles_per_element
      real(dp) :: dt_fraction
      integer :: margin_cells
      character(len=32) :: kernels
      real(dp) :: periods, end_time
      character(len=1024) :: file
      logical :: history
      real(dp) :: snapshot_times(max_snapshots)
      namelist /scene/ kind, length, youngs_modulus, density, velocity_amplitude, mode
      namelist /discretisation/ scheme, elements, particles_per_element, dt_fraction, margin_cells, kernels
      namelist /run/ periods, end_time
      namelist /output/ file, history, snapshot_times
      real(dp) :: energy_growth_limit, max_cell_move
      namelist /guards/ energy_growth_limit, max_cell_move

      character(len=16), allocatable :: found(:)
      character(len=16), allocatable :: known(:)
      integer :: unit, stat, i
      character(len=512) :: msg

      config = config_t()
      kind = config%scene_kind
      length = config%length
      youngs_modulus = config%youngs_modulus
      density = config%density
      velocity_amplitude = config%velocity_amplitude
      mode = config%mode
      scheme = config%scheme
      elements = config%elements
      particles_per_element = config%particles_per_element
      dt_fraction = config%dt_fraction
      margin_cells = config%margin_cells
      kernels = config%kernels
      periods = unset
      end_time = unset
      file = config%file
      history = config%history
      snapshot_times = unset
      energy_growth_limit = config%energy_growth_limit
      max_cell_move = config%max_cell_move

      known = [character(len=16) :: 'scene', 'discretisation', 'run', 'output', 'guards']
      if (present(extra_groups)) known = [character(len=16) :: known, extra_groups]
      call scan_groups(path, known, found, error)
      if (allocated(error)) return

      open (newunit=unit, file=path, status='old', action='read', iostat=stat, iomsg=msg)
      if (stat /= 0) then
         call set_error(error, "cannot open input file '"//trim(path)//"': "//trim(msg))
         return
      end if
      do i = 1, size(found)
         rewind (unit)
         select case (trim(found(i)))
         case ('scene')
            read (unit, nml=scene, iostat=stat, iomsg=msg)
         case ('discretisation')
            read (unit, nml=discretisation, iostat=stat, iomsg=msg)
         case ('run')
            read (unit, nml=run, iostat=stat, iomsg=msg)
         case ('output')
            read (unit, nml=output, iostat=stat, iomsg=msg)
         case ('guards')
            read (unit, nml=guards, iostat=stat, iomsg=msg)
         case default
            cycle ! a group another reader handles
         end select
         if (stat /= 0) call append_error(error, read_group_error(path, found(i), group_names(found(i)), stat, msg))
      end do
      close (unit)
      if (allocated(error)) return

      config%scene_kind = kind
      config%length = length
      config%youngs_modulus = youngs_modulus
      config%density = density
      config%velocity_amplitude = velocity_amplitude
      config%mode = mode
      config%scheme = scheme
      if (len_trim(scheme) > len(config%scheme)) config%scheme = '?'//scheme
      config%elements = elements
      config%particles_per_element = particles_per_element
      config%dt_fraction = dt_fraction
      config%margin_cells = margin_cells
      config%kernels = kernels
      if (len_trim(kernels) > len(config%kernels)) config%kernels = '?'//kernels
      if (periods /= unset .and. end_time /= unset) then
         call append_error(error, "run: give either periods or end_time, not both")
      else if (end_time /= unset) then
         config%end_time = end_time
         config%periods = unset
      else if (periods /= unset) then
         config%periods = periods
      end if
      config%file = file
      config%history = history
      config%energy_growth_limit = energy_growth_limit
      config%max_cell_move = max_cell_move
      config%snapshot_count = count(snapshot_times /= unset)
      if (any(snapshot_times(config%snapshot_count + 1:) /= unset)) then
         call append_error(error, "output: snapshot_times must be given as one contiguous list")
      end if
      config%snapshot_times = 0.0_dp
      config%snapshot_times(1:config%snapshot_count) = snapshot_times(1:config%snapshot_count)
      call validate_config(config, error)
      if (allocated(error)) return
      call resolve_config(config)
   end subroutine read_config

   !> The message for a failed namelist read: file, group, and the variable at fault.
   !> gfortran reports only the token it could not match ("Cannot match namelist object name X");
   !> X followed by '=' is an unknown name, otherwise it is the tail of a bad value and the culprit
   !> is the variable assigned just before it.
   function read_group_error(path, group, names, stat, msg) result(text)
      character(len=*), intent(in) :: path, group, names, msg
      integer, intent(in) :: stat
      character(len=:), allocatable :: text, body, token, variable
      character(len=*), parameter :: no_match = 'Cannot match namelist object name '
      integer :: k, j, start
      text = trim(path)//": group &"//trim(group)//": "
      if (stat < 0) then
         text = text//"not terminated by '/' (end of file reached)"
         return
      end if
      k = index(msg, no_match)
      if (k == 0) then
         ! e.g. "Integer overflow while reading item 1": name the variables the group assigns
         text = text//trim(msg)//" (variables given: "//assigned_names(lower(group_text(path, group)))//")"
         return
      end if
      token = lower(trim(msg(k + len(no_match):)))
      body = lower(group_text(path, group))
      k = index(body, token)
      if (k == 0) then
         text = text//trim(msg)
         return
      end if
      if (index(adjustl(body(k + len(token):)), '=') == 1) then
         text = text//"unknown variable '"//token//"'; allowed names: "//names
         return
      end if
      j = index(body(1:k - 1), '=', back=.true.)
      start = j - 1
      do while (start > 1)
         if (body(start:start) /= ' ') exit
         start = start - 1
      end do
      variable = ''
      do while (start >= 1)
         if (scan(body(start:start), identifier_characters) == 0) exit
         variable = body(start:start)//variable
         start = start - 1
      end do
      text = text//"bad value for '"//variable//"' near '"//token// &
             "': not of the variable's type (integers take no decimal point, text needs quotes)"
   end function read_group_error

   !> The names assigned (`name =`) in a group's text, comma separated.
   function assigned_names(body) result(names)
      character(len=*), intent(in) :: body
      character(len=:), allocatable :: names
      integer :: i, start, end
      names = ''
      do i = 1, len(body)
         if (body(i:i) /= '=') cycle
         if (index(body(1:i), '/') > 0) exit ! end of the group
         end = i - 1
         do while (end > 1)
            if (body(end:end) /= ' ') exit
            end = end - 1
         end do
         start = end
         do while (start > 1)
            if (scan(body(start - 1:start - 1), identifier_characters) == 0) exit
            start = start - 1
         end do
         if (len(names) > 0) names = names//', '
         names = names//body(start:end)
      end do
   end function assigned_names

   !> The text of group &group in file `path`, from '&group' up to the end of the file (for messages).
   function group_text(path, group) result(text)
      character(len=*), intent(in) :: path, group
      character(len=:), allocatable :: text
      character(len=4096) :: line
      integer :: unit, stat, k
      logical :: inside
      text = ''
      inside = .false.
      open (newunit=unit, file=path, status='old', action='read', iostat=stat)
      if (stat /= 0) return
      do
         read (unit, '(a)', iostat=stat) line
         if (stat /= 0) exit
         if (.not. inside) then
            k = index(lower(line), '&'//trim(group))
            if (k == 0) cycle
            inside = .true.
            line = line(k + len_trim(group) + 1:)
         end if
         text = text//' '//trim(line)
      end do
      close (unit)
   end function group_text

   !> List the namelist groups that `path` contains, in file order. Unknown or repeated group
   !> names are errors (gfortran would silently skip a misspelled group and use defaults).
   subroutine scan_groups(path, known, present, error)
      character(len=*), intent(in) :: path
      character(len=*), intent(in) :: known(:)
      character(len=16), allocatable, intent(out) :: present(:)
      type(error_t), allocatable, intent(out) :: error
      integer :: unit, stat, line_number
      logical :: is_folder
      character(len=4096) :: line
      character(len=512) :: msg
      character(len=:), allocatable :: name

      allocate (present(0))
      inquire (file=trim(path)//'/.', exist=is_folder)
      if (is_folder) then
         call set_error(error, "input file '"//trim(path)//"' is a folder; allowed: a namelist file")
         return
      end if
      open (newunit=unit, file=path, status='old', action='read', iostat=stat, iomsg=msg)
      if (stat /= 0) then
         call set_error(error, "cannot open input file '"//trim(path)//"': "//trim(msg))
         return
      end if
      line_number = 0
      do
         read (unit, '(a)', iostat=stat, iomsg=msg) line
         if (is_iostat_end(stat)) exit
         if (stat /= 0) then
            call append_error(error, "cannot read input file '"//trim(path)//"': "//trim(msg))
            exit
         end if
         line_number = line_number + 1
         call groups_in_line(line)
      end do
      close (unit)
   contains
      !> Every '&name' of the line outside quoted strings and comments.
      subroutine groups_in_line(text)
         character(len=*), intent(in) :: text
         integer :: i, last
         character(len=1) :: quote
         quote = ' '
         i = 0
         do while (i < len_trim(text))
            i = i + 1
            if (quote /= ' ') then
               if (text(i:i) == quote) quote = ' '
               cycle
            end if
            select case (text(i:i))
            case ("'", '"')
               quote = text(i:i)
            case ('!')
               return
            case ('&')
               last = i
               do while (last < len(text))
                  if (scan(text(last + 1:last + 1), identifier_characters) == 0) exit
                  last = last + 1
               end do
               name = lower(text(i + 1:last))
               i = last
               if (len(name) == 0 .or. name == 'end') cycle
               if (.not. any(known == name)) then
                  call append_error(error, trim(path)//":"//str(line_number)//": unknown namelist group &"//name// &
                                    " (known groups: "//join(known)//")")
               else if (any(present == name)) then
                  call append_error(error, trim(path)//":"//str(line_number)//": group &"//name//" is given twice")
               else
                  present = [character(len=16) :: present, name]
               end if
            end select
         end do
      end subroutine groups_in_line
   end subroutine scan_groups

   !> Check every value; append one line per problem to `error`, naming the variable and range.
   !> `with_system = .false.` skips the checks against the machine (memory available, output folder),
   !> which a sweep makes once for its largest case instead of once per case.
   subroutine validate_config(config, error, with_system)
      type(config_t), intent(in) :: config
      type(error_t), allocatable, intent(inout) :: error
      logical, intent(in), optional :: with_system
      real(dp) :: c, dx, dt, end_time
      integer(i8) :: particles

      if (trim(config%scene_kind) /= 'vibrating_bar') call append_error(error, &
         "scene: kind = '"//trim(config%scene_kind)//"' is unknown; allowed: 'vibrating_bar'")
      call positive(config%length, 'scene: length', 'm')
      call positive(config%youngs_modulus, 'scene: youngs_modulus', 'Pa')
      call positive(config%density, 'scene: density', 'kg/m^3')
      if (.not. ieee_is_finite(config%velocity_amplitude)) call append_error(error, &
         "scene: velocity_amplitude = "//str(config%velocity_amplitude)//" is not finite; allowed: any finite real (m/s)")
      if (config%mode < 1) call append_error(error, &
         "scene: mode = "//str(config%mode)//" is out of range; allowed: integer >= 1")
      if (.not. is_known_scheme(config%scheme)) call append_error(error, &
         "discretisation: scheme = '"//trim(config%scheme)//"' is unknown; allowed: "//known_schemes)
      if (config%elements < 1) call append_error(error, &
         "discretisation: elements = "//str(config%elements)//" is out of range; allowed: integer >= 1")
      if (config%particles_per_element < 1) call append_error(error, &
         "discretisation: particles_per_element = "//str(config%particles_per_element)// &
         " is out of range; allowed: integer >= 1")
      particles = int(max(config%elements, 0), i8)*int(max(config%particles_per_element, 0), i8)
      if (particles > max_count) call append_error(error, &
         "discretisation: elements*particles_per_element = "//str(particles)//" is too large; allowed: <= "// &
         str(max_count))
      if (.not. ieee_is_finite(config%dt_fraction) .or. config%dt_fraction <= 0.0_dp &
          .or. config%dt_fraction > max_dt_fraction) call append_error(error, &
         "discretisation: dt_fraction = "//str(config%dt_fraction)//" is out of range; allowed: 0 < dt_fraction <= "// &
         str(max_dt_fraction)//" (fraction of the critical step dx/c)")
      if (config%margin_cells < -1) call append_error(error, &
         "discretisation: margin_cells = "//str(config%margin_cells)//" is out of range; allowed: -1 (automatic: "// &
         "the scene's expected motion + 2 cells) or integer >= 0")
      if (trim(config%kernels) /= 'auto' .and. trim(config%kernels) /= 'generic') call append_error(error, &
         "discretisation: kernels = '"//trim(config%kernels)//"' is unknown; allowed: 'auto', 'generic'")
      if (config%end_time /= unset) then
         call positive(config%end_time, 'run: end_time', 's')
      else
         call positive(config%periods, 'run: periods', '')
      end if
      if (.not. ieee_is_finite(config%energy_growth_limit) .or. config%energy_growth_limit <= 1.0_dp) &
         call append_error(error, "guards: energy_growth_limit = "//str(config%energy_growth_limit)// &
                           " is out of range; allowed: finite real > 1 (factor of the initial energy)")
      if (.not. ieee_is_finite(config%max_cell_move) .or. config%max_cell_move <= 0.0_dp) &
         call append_error(error, "guards: max_cell_move = "//str(config%max_cell_move)// &
                           " is out of range; allowed: finite real > 0 (cells per step)")
      if (len_trim(config%file) == 0) call append_error(error, "output: file is empty; allowed: a file name ending in .h5")
      if (config%snapshot_count > 0) then
         if (.not. all(ieee_is_finite(config%snapshot_times(1:config%snapshot_count))) .or. &
             any(config%snapshot_times(1:config%snapshot_count) < 0.0_dp)) call append_error(error, &
            "output: snapshot_times must be finite and >= 0 (seconds)")
      end if
      if (allocated(error)) return

      ! Consistency checks that need the resolved quantities.
      c = sqrt(config%youngs_modulus/config%density)
      dx = config%length/config%elements
      dt = config%dt_fraction*dx/c
      if (.not. ieee_is_finite(c) .or. .not. ieee_is_finite(dt) .or. dt <= 0.0_dp) then
         call append_error(error, "scene: youngs_modulus/density = "//str(config%youngs_modulus/config%density)// &
                           " gives no finite positive wave speed and time step")
         return
      end if
      end_time = run_end_time(config)
      if (end_time < dt) call append_error(error, "run: end time "//str(end_time)// &
         " s is shorter than one time step dt = "//str(dt)//" s; allowed: end time >= dt")
      if (end_time/dt > real(huge(1) - 1, dp)) call append_error(error, "run: end time / dt = "// &
         str(end_time/dt)//" steps is too many; allowed: <= "//str(huge(1) - 1))
      if (config%snapshot_count > 0) then
         if (any(config%snapshot_times(1:config%snapshot_count) > end_time*(1.0_dp + 1.0e-12_dp))) &
            call append_error(error, "output: snapshot_times must lie within the run, 0 to "//str(end_time)//" s")
      end if
      if (allocated(error)) return
      if (present(with_system)) then
         if (.not. with_system) return
      end if
      call check_memory(particles, config%elements, merge(step_count(end_time, dt), 0, config%history), error)
      call check_output_path(config%file, 'output: file', error)
   contains
      subroutine positive(value, name, unit)
         real(dp), intent(in) :: value
         character(len=*), intent(in) :: name, unit
         if (.not. ieee_is_finite(value) .or. value <= 0.0_dp) then
            if (len(unit) > 0) then
               call append_error(error, name//" = "//str(value)//" is out of range; allowed: finite real > 0 ("//unit//")")
            else
               call append_error(error, name//" = "//str(value)//" is out of range; allowed: finite real > 0")
            end if
         end if
      end subroutine positive
   end subroutine validate_config

   !> Refuse a run whose particles and grid would not fit in the memory available now.
   !> `history_steps` is the number of history entries kept (0 without history).
   subroutine check_memory(particles, elements, history_steps, error)
      integer(i8), intent(in) :: particles
      integer, intent(in) :: elements, history_steps
      type(error_t), allocatable, intent(inout) :: error
      integer(i8) :: needed, available
      integer, parameter :: bytes_per_element = 10*8 ! grid: 5 element shares + 5 nodal arrays
      integer, parameter :: bytes_per_history_entry = 5*8
      needed = particles*bytes_per_particle + int(max(elements, 0), i8)*bytes_per_element + &
               int(history_steps, i8)*bytes_per_history_entry
      available = available_memory()
      if (available > 0 .and. needed > available) call append_error(error, &
         "discretisation: elements = "//str(elements)//" and particles_per_element give "//str(particles)// &
         " particles; with "//str(history_steps)//" history steps the run needs "//str(needed/1024**2)// &
         " MiB; allowed: at most the "//str(available/1024**2)//" MiB of memory available")
   end subroutine check_memory

   !> The output file's folder must exist (the file is written there under a temporary name first).
   subroutine check_output_path(path, name, error)
      character(len=*), intent(in) :: path, name
      type(error_t), allocatable, intent(inout) :: error
      integer :: slash
      logical :: exists
      slash = index(trim(path), '/', back=.true.)
      if (slash > 1) then
         inquire (file=path(1:slash - 1)//'/.', exist=exists)
         if (.not. exists) call append_error(error, name//" = '"//trim(path)//"': folder '"//path(1:slash - 1)// &
                                             "' does not exist; allowed: a path in an existing folder")
      end if
      if (slash == len_trim(path)) call append_error(error, name//" = '"//trim(path)//"' names a folder; allowed: a file name")
   end subroutine check_output_path

   real(dp) function run_end_time(config)
      type(config_t), intent(in) :: config
      real(dp) :: omega
      if (config%end_time /= unset) then
         run_end_time = config%end_time
      else
         omega = (2*config%mode - 1)*pi/(2.0_dp*config%length)*sqrt(config%youngs_modulus/config%density)
         run_end_time = config%periods*2.0_dp*pi/omega
      end if
   end function run_end_time

   !> The time-step fraction above which `scheme` with `particles_per_element` is linearly unstable
   !> on fine meshes (studies/stability/linear_stability.py, 20 elements; coarser meshes allow a
   !> little more). Used to warn, not to refuse: stability studies go beyond it on purpose.
   pure real(dp) function stability_limit(scheme, particles_per_element)
      character(len=*), intent(in) :: scheme
      integer, intent(in) :: particles_per_element
      real(dp), parameter :: usl(8) = [0.7079_dp, 0.7568_dp, 0.7670_dp, 0.7706_dp, 0.7724_dp, 0.7733_dp, &
                                       0.7739_dp, 0.7742_dp]
      real(dp), parameter :: usf(8) = [2.0062_dp, 1.7332_dp, 1.6784_dp, 1.6601_dp, 1.6503_dp, 1.6450_dp, &
                                       1.6418_dp, 1.6398_dp]
      integer :: k
      k = min(max(particles_per_element, 1), 8)
      if (trim(scheme) == 'usl') then
         stability_limit = usl(k)
      else ! USF and MUSL share their linear spectrum
         stability_limit = usf(k)
      end if
   end function stability_limit

   !> The variables of each group, for messages.
   function group_names(group) result(names)
      character(len=*), intent(in) :: group
      character(len=:), allocatable :: names
      select case (trim(group))
      case ('scene')
         names = 'kind, length, youngs_modulus, density, velocity_amplitude, mode'
      case ('discretisation')
         names = 'scheme, elements, particles_per_element, dt_fraction, margin_cells, kernels'
      case ('run')
         names = 'periods, end_time'
      case ('output')
         names = 'file, history, snapshot_times'
      case ('guards')
         names = 'energy_growth_limit, max_cell_move'
      case default
         names = '(see mpm1d --help)'
      end select
   end function group_names

   !> The smallest n with n*dt >= end_time, robust to round-off: a ratio within a few ulps of an
   !> integer counts as that integer (so 2 periods at 10% of dx/c give exactly 8*elements/0.1 steps).
   integer function step_count(end_time, dt)
      real(dp), intent(in) :: end_time, dt
      real(dp) :: ratio
      ratio = end_time/dt
      step_count = nint(ratio)
      if (abs(ratio - step_count) > 1.0e-9_dp*max(1.0_dp, ratio)) step_count = ceiling(ratio)
      step_count = max(step_count, 1)
   end function step_count

   !> Fill the derived quantities of a validated configuration.
   subroutine resolve_config(config)
      type(config_t), intent(inout) :: config
      real(dp) :: omega
      config%wave_speed = sqrt(config%youngs_modulus/config%density)
      config%dx = config%length/config%elements
      config%dt = config%dt_fraction*config%dx/config%wave_speed
      omega = (2*config%mode - 1)*pi/(2.0_dp*config%length)*config%wave_speed
      config%period = 2.0_dp*pi/omega
      config%final_time = run_end_time(config)
      config%steps = step_count(config%final_time, config%dt)
   end subroutine resolve_config

   !> Echo the configuration as a namelist file that reproduces the run.
   subroutine write_config_namelist(unit, config)
      integer, intent(in) :: unit
      type(config_t), intent(in) :: config
      write (unit, '(a)') config_namelist(config)
   end subroutine write_config_namelist

   !> The configuration as namelist text (one group per line) that reproduces the run.
   function config_namelist(config) result(text)
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: text
      character(len=*), parameter :: nl = new_line('a')
      text = "&scene kind='"//trim(config%scene_kind)//"', length="//str(config%length)// &
             ", youngs_modulus="//str(config%youngs_modulus)//", density="//str(config%density)// &
             ", velocity_amplitude="//str(config%velocity_amplitude)//", mode="//str(config%mode)//" /"//nl// &
             "&discretisation scheme='"//trim(config%scheme)//"', elements="//str(config%elements)// &
             ", particles_per_element="//str(config%particles_per_element)//", dt_fraction="// &
             str(config%dt_fraction)//", margin_cells="//str(config%margin_cells)//", kernels='"// &
             trim(config%kernels)//"' /"//nl
      if (config%end_time /= unset) then
         text = text//"&run end_time="//str(config%end_time)//" /"//nl
      else
         text = text//"&run periods="//str(config%periods)//" /"//nl
      end if
      text = text//"&output file='"//trim(config%file)//"', history="//merge('T', 'F', config%history)// &
             snapshot_list()//" /"//nl//"&guards energy_growth_limit="//str(config%energy_growth_limit)// &
             ", max_cell_move="//str(config%max_cell_move)//" /"
   contains
      function snapshot_list() result(list)
         character(len=:), allocatable :: list
         integer :: i
         list = ''
         if (config%snapshot_count == 0) return
         list = ', snapshot_times='
         do i = 1, config%snapshot_count
            list = list//str(config%snapshot_times(i))
            if (i < config%snapshot_count) list = list//','
         end do
      end function snapshot_list
   end function config_namelist

   !> One line describing the run for progress and log messages.
   function config_summary(config) result(text)
      type(config_t), intent(in) :: config
      character(len=:), allocatable :: text
      text = trim(config%scheme)//", "//str(config%elements)//" elements, "//str(config%particles_per_element)// &
             " particles per element, dt = "//str(config%dt_fraction)//" dx/c = "//str(config%dt)//" s, "// &
             str(config%steps)//" steps"
   end function config_summary

   pure function join(words) result(text)
      character(len=*), intent(in) :: words(:)
      character(len=:), allocatable :: text
      integer :: i
      text = ''
      do i = 1, size(words)
         text = text//'&'//trim(words(i))
         if (i < size(words)) text = text//', '
      end do
   end function join
end module mpm_config
