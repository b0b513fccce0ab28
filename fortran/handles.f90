!> Objects the kernel keeps between calls (contact tables, transient problems), each
!> under an integer handle.
!>
!> A registry holds any kind of object (class(*)); the module that owns a kind keeps
!> one registry and turns what find_item returns back into its type.  A handle is
!> generation * slot_span + slot.  Each slot counts how often it has been taken (its
!> generation), so a freed handle no longer matches once its slot is reused: a stale
!> handle gets an error instead of another object (until the same slot has been
!> reused max_generation times).  0 and negative numbers are never handles.  The
!> registries are not thread-safe: every caller holds Python's GIL (the f2py wrappers
!> do not release it).
module handles
  use kinds, only: ik
  implicit none
  private

  public :: handle_registry, keep_item, find_item, release_item
  public :: hd_ok, hd_err_handle, hd_err_full

  integer(ik), parameter :: hd_ok = 0          !< success
  integer(ik), parameter :: hd_err_handle = 1  !< not a live handle (never issued, or freed)
  integer(ik), parameter :: hd_err_full = 2    !< every slot is in use

  integer(ik), parameter :: slot_span = 65536       !< slots a registry holds at most, plus one
  integer(ik), parameter :: max_generation = 32767  !< keeps a handle below 2**31
  integer(ik), parameter :: first_capacity = 8      !< slots of a new registry

  !> One slot: the object kept there (unallocated when free) and its generation.
  type :: registry_slot
    class(*), allocatable :: item       !< the object, any type
    integer(ik) :: generation = 0       !< times the slot has been taken [-]
  end type registry_slot

  !> The objects of one kind, by slot.
  type :: handle_registry
    private
    type(registry_slot), allocatable :: slots(:)  !< grows by doubling
  end type handle_registry

contains

  !> Keep a copy of item in a free slot (growing the registry when all are taken) and
  !> issue its handle.
  subroutine keep_item(registry, item, handle, ierr)
    type(handle_registry), intent(inout) :: registry  !< the registry of item's kind
    class(*), intent(in) :: item                      !< the object to keep
    integer(ik), intent(out) :: handle                !< the new handle, 0 on error [-]
    integer(ik), intent(out) :: ierr                  !< error code (0 = ok)
    type(registry_slot), allocatable :: grown(:)
    integer(ik) :: slot, capacity, i

    handle = 0
    ierr = hd_ok
    if (.not. allocated(registry%slots)) allocate (registry%slots(first_capacity))
    capacity = int(size(registry%slots), ik)
    do slot = 1, capacity
      if (.not. allocated(registry%slots(slot)%item)) exit
    end do
    if (slot > capacity) then
      if (capacity >= slot_span - 1) then
        ierr = hd_err_full
        return
      end if
      allocate (grown(min(2 * capacity, slot_span - 1)))
      do i = 1, capacity  ! move, not copy: the objects stay where they are
        grown(i)%generation = registry%slots(i)%generation
        call move_alloc(registry%slots(i)%item, grown(i)%item)
      end do
      call move_alloc(grown, registry%slots)
    end if
    associate (taken => registry%slots(slot))
      taken%generation = modulo(taken%generation, max_generation) + 1
      allocate (taken%item, source=item)
      handle = taken%generation * slot_span + slot
    end associate
  end subroutine keep_item

  !> The object a live handle names, for as long as no item is kept in or released
  !> from the registry.
  subroutine find_item(registry, handle, item, ierr)
    type(handle_registry), target, intent(in) :: registry  !< the registry of the kind asked for
    integer(ik), intent(in) :: handle                      !< handle from keep_item [-]
    class(*), pointer, intent(out) :: item                 !< the object, null on error
    integer(ik), intent(out) :: ierr                       !< error code (0 = ok)
    integer(ik) :: slot

    nullify (item)
    call find_slot(registry, handle, slot, ierr)
    if (ierr /= hd_ok) return
    item => registry%slots(slot)%item
  end subroutine find_item

  !> Release the object a live handle names; the handle is no longer valid.
  subroutine release_item(registry, handle, ierr)
    type(handle_registry), intent(inout) :: registry  !< the registry of the kind
    integer(ik), intent(in) :: handle                 !< handle to free [-]
    integer(ik), intent(out) :: ierr                  !< error code (0 = ok)
    integer(ik) :: slot

    call find_slot(registry, handle, slot, ierr)
    if (ierr /= hd_ok) return
    deallocate (registry%slots(slot)%item)
  end subroutine release_item

  !> The slot of a live handle.
  pure subroutine find_slot(registry, handle, slot, ierr)
    type(handle_registry), intent(in) :: registry  !< the registry
    integer(ik), intent(in) :: handle              !< handle from keep_item [-]
    integer(ik), intent(out) :: slot               !< its slot, 0 on error [-]
    integer(ik), intent(out) :: ierr               !< error code (0 = ok)

    slot = 0
    ierr = hd_err_handle
    if (.not. allocated(registry%slots) .or. handle <= 0) return
    if (modulo(handle, slot_span) < 1 .or. modulo(handle, slot_span) > size(registry%slots)) return
    associate (candidate => registry%slots(modulo(handle, slot_span)))
      if (.not. allocated(candidate%item) .or. candidate%generation /= handle / slot_span) return
    end associate
    slot = modulo(handle, slot_span)
    ierr = hd_ok
  end subroutine find_slot
end module handles
