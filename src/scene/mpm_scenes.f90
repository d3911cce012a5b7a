!> The one place that knows every scene kind: one line each in `scene_input`, which makes the input of
!> kind number k (its parameters at their defaults). Everything else asks the input (mpm_scene_input):
!> its name and description, its registry entries, its checks, the scene it makes.
module mpm_scenes
   use mpm_scene_input, only: scene_input_t, scene_kind_t
   use mpm_scene_bar, only: bar_input_t
   use mpm_scene_column, only: column_input_t
   use mpm_scene_manufactured, only: manufactured_input_t
   use mpm_scene_composite, only: composite_input_t
   use mpm_scene_impact, only: impact_input_t
   use mpm_scene_plastic_wave, only: plastic_wave_input_t
   implicit none
   private
   public :: scene_input_t, scene_kind_t, scene_slot_t, scene_input, scene_catalog, scene_kinds, known_scenes, &
             new_scene_input, default_scene

   !> The kind a run has when the input names none.
   character(len=*), parameter :: default_scene = 'vibrating_bar'

   !> One scene input (an array of them holds one of each kind).
   type :: scene_slot_t
      class(scene_input_t), allocatable :: input
   end type scene_slot_t

contains

   !> The input of scene kind number `k` at its defaults, in the order of --help (unallocated past the last).
   subroutine scene_input(k, input)
      integer, intent(in) :: k
      class(scene_input_t), allocatable, intent(out) :: input
      select case (k)
      case (1)
         allocate (input, source=bar_input_t())
      case (2)
         allocate (input, source=column_input_t())
      case (3)
         allocate (input, source=manufactured_input_t())
      case (4)
         allocate (input, source=composite_input_t())
      case (5)
         allocate (input, source=impact_input_t())
      case (6)
         allocate (input, source=plastic_wave_input_t())
      end select
   end subroutine scene_input

   !> One input of every kind, at its defaults.
   subroutine scene_catalog(slots)
      type(scene_slot_t), allocatable, intent(out) :: slots(:)
      class(scene_input_t), allocatable :: input
      type(scene_slot_t), allocatable :: more(:)
      integer :: k
      allocate (slots(0))
      k = 0
      do
         call scene_input(k + 1, input)
         if (.not. allocated(input)) exit
         k = k + 1
         allocate (more(k))
         more(1:k - 1) = slots
         call move_alloc(input, more(k)%input)
         call move_alloc(more, slots)
      end do
   end subroutine scene_catalog

   !> Every kind's description, in the order of the catalog.
   function scene_kinds() result(kinds)
      type(scene_kind_t), allocatable :: kinds(:)
      type(scene_slot_t), allocatable :: slots(:)
      integer :: k
      call scene_catalog(slots)
      allocate (kinds(size(slots)))
      do k = 1, size(slots)
         kinds(k) = slots(k)%input%describe()
      end do
   end function scene_kinds

   !> The kinds' names, comma separated ('vibrating_bar, column, ...').
   function known_scenes() result(names)
      character(len=:), allocatable :: names
      type(scene_kind_t), allocatable :: kinds(:)
      integer :: k
      kinds = scene_kinds()
      names = ''
      do k = 1, size(kinds)
         if (k > 1) names = names//', '
         names = names//trim(kinds(k)%name)
      end do
   end function known_scenes

   !> The input of kind `name` at its defaults; unallocated when no kind has that name.
   subroutine new_scene_input(name, input)
      character(len=*), intent(in) :: name
      class(scene_input_t), allocatable, intent(out) :: input
      integer :: k
      k = 0
      do
         k = k + 1
         call scene_input(k, input)
         if (.not. allocated(input)) return
         if (trim(input%describe_name()) == trim(name)) return
      end do
   end subroutine new_scene_input
end module mpm_scenes
