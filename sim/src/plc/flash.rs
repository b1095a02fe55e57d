//! The user flash through the protocol: the page lists (DATA_ASK, SYSTEM_ASK,
//! PROGRAM_ASK), page lengths, and pages read and written in packets of ExchPackSize.
//! Only `Plc::dispatch` calls these, after the registry's login and stop conditions;
//! loading the pages into the VM is `Plc::reset`'s business, not this module's.

use gutta_format::{PageId, PageKind};
use gutta_protocol::function::{PageArea, PageRef};

use super::window::ConnectionId;
use super::{Plc, Refusal, LAST_PACKET};

impl Plc {
    /// DATA_ASK, SYSTEM_ASK, PROGRAM_ASK: the numbers of the pages present (for the
    /// program: the instruction pages).
    pub(super) fn page_list(&self, area: PageArea) -> Vec<u8> {
        let kind = match area {
            PageArea::Data => PageKind::Data,
            PageArea::System => PageKind::System,
            PageArea::Program => PageKind::Instruction,
        };
        self.pages
            .keys()
            .filter(|id| id.kind == kind)
            .map(|id| id.number)
            .collect()
    }

    /// A page ASK: the page's length; a page that is not there fails.
    pub(super) fn page_length(&self, page: PageRef) -> Result<u16, Refusal> {
        let len = self
            .pages
            .get(&page.page_id())
            .ok_or(Refusal::NoSuchPage)?
            .len();
        Ok(u16::try_from(len).unwrap_or(u16::MAX))
    }

    /// A page READ: packet `packet`'s bytes, from packet x ExchPackSize up to
    /// ExchPackSize or the page's end.
    pub(super) fn read_page(&self, page: PageRef, packet: u16) -> Result<Vec<u8>, Refusal> {
        let bytes = self.pages.get(&page.page_id()).ok_or(Refusal::NoSuchPage)?;
        let size = self.pack_size();
        let start = usize::from(packet & !LAST_PACKET) * size;
        if start > bytes.len() || (start == bytes.len() && start > 0) {
            return Err(Refusal::BadPacket);
        }
        let end = bytes.len().min(start + size);
        Ok(bytes[start..end].to_vec())
    }

    /// A page WRITE: only inside the download window `from`'s PLC_CLEAR opened (the
    /// registry's stop condition was checked before), so every page in flash at a
    /// reset was written by one connection in one window.
    pub(super) fn write_page(
        &mut self,
        from: ConnectionId,
        page: PageRef,
        packet: u16,
        data: &[u8],
    ) -> Result<(), Refusal> {
        if self.window.map(|w| w.owner) != Some(from) {
            return Err(Refusal::FlashLocked);
        }
        self.write_packet(page.page_id(), packet, data)
    }

    fn pack_size(&self) -> usize {
        (self.target.plc.exch_pack_size as usize).max(1)
    }

    /// A write packet: packet 0 starts the page, each next packet continues at
    /// packet x ExchPackSize; the last packet ends the page.
    fn write_packet(&mut self, id: PageId, packet: u16, payload: &[u8]) -> Result<(), Refusal> {
        let size = self.pack_size();
        let number = usize::from(packet & !LAST_PACKET);
        let last = packet & LAST_PACKET != 0;
        if payload.len() > size || (!last && payload.len() != size) {
            return Err(Refusal::BadPacket);
        }
        let page = self.pages.entry(id).or_default();
        if number == 0 {
            page.clear();
        } else if page.len() != number * size {
            return Err(Refusal::BadPacket);
        }
        page.extend_from_slice(payload);
        Ok(())
    }
}
